#include "render/assets.h"

#include <algorithm>
#include <cstdlib>
#include <system_error>

#include "core/error.h"

namespace matlas {

namespace {

std::filesystem::path executable_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

std::string install_hint() {
  return " (install the assets with scripts/install-assets.sh, or set MATLAS_ASSETS)";
}

}  // namespace

std::optional<std::filesystem::path> assets_dir() {
  std::vector<std::filesystem::path> candidates;
  if (const char* env = std::getenv("MATLAS_ASSETS"); env && *env) candidates.emplace_back(env);
  if (const auto exe = executable_dir(); !exe.empty()) {
    candidates.push_back(exe / ".." / "assets");
    candidates.push_back(exe / "assets");
  }
  candidates.emplace_back("assets");
  for (const auto& c : candidates) {
    std::error_code ec;
    if (std::filesystem::is_directory(c, ec)) return std::filesystem::weakly_canonical(c, ec);
  }
  return std::nullopt;
}

std::vector<std::string> installed_environments() {
  std::vector<std::string> names;
  const auto dir = assets_dir();
  std::error_code ec;
  if (!dir || !std::filesystem::is_directory(*dir / "hdri", ec)) return names;
  for (const auto& e : std::filesystem::directory_iterator(*dir / "hdri", ec))
    if (e.path().extension() == ".exr") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::filesystem::path resolve_environment(const std::string& name_or_path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(name_or_path, ec)) return name_or_path;
  if (const auto dir = assets_dir()) {
    const auto p = *dir / "hdri" / (name_or_path + ".exr");
    if (std::filesystem::is_regular_file(p, ec)) return p;
  }
  std::string known;
  for (const auto& n : installed_environments()) known += (known.empty() ? "" : ", ") + n;
  throw Error("environment map '" + name_or_path + "': no such file or installed map" +
              (known.empty() ? install_hint() : " (installed: " + known + ")"));
}

std::filesystem::path resolve_mesh(const std::string& name_or_path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(name_or_path, ec)) return name_or_path;
  const std::string name = name_or_path == "suzanne" ? "suzi" : name_or_path;
  if (const auto dir = assets_dir()) {
    const auto p = *dir / "models" / (name + ".glb");
    if (std::filesystem::is_regular_file(p, ec)) return p;
  }
  throw Error("mesh '" + name_or_path + "': no such file or installed model" + install_hint());
}

}  // namespace matlas
