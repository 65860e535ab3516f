#include "server/web_root.h"

#include <cstdlib>
#include <system_error>

#include "core/error.h"

namespace matlas::server {

namespace {
bool has_index(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_regular_file(dir / "index.html", ec);
}
}  // namespace

std::filesystem::path executable_path() {
  std::error_code ec;
  auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : p;
}

std::optional<std::filesystem::path> find_web_root(const std::filesystem::path& explicit_dir) {
  if (!explicit_dir.empty()) {
    if (!has_index(explicit_dir))
      throw file_error(explicit_dir, "not a built web UI folder (no index.html); run `npm ci && npm run build` in web/");
    return std::filesystem::absolute(explicit_dir);
  }
  if (const char* env = std::getenv("MATLAS_WEB_ROOT"); env && *env) {
    if (!has_index(env))
      throw file_error(env, "MATLAS_WEB_ROOT is not a built web UI folder (no index.html)");
    return std::filesystem::absolute(env);
  }
  const auto exe = executable_path();
  if (exe.empty()) return std::nullopt;
  const auto dir = exe.parent_path();
  for (const auto& candidate : {dir / "web" / "dist", dir / ".." / "web" / "dist",
                                dir / ".." / ".." / "web" / "dist", dir / ".." / "share" / "matlas" / "web"}) {
    if (has_index(candidate)) return std::filesystem::weakly_canonical(candidate);
  }
  return std::nullopt;
}

}  // namespace matlas::server
