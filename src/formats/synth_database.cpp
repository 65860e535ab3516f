#include "formats/synth_database.h"

#include <set>
#include <string>
#include <system_error>

#include "brdf/tabulate.h"
#include "core/error.h"
#include "formats/merl_file.h"

namespace matlas {

namespace fs = std::filesystem;

namespace {

bool plain_file_name(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return false;
  for (const char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
                    ch == '.' || ch == '-' || ch == '_';
    if (!ok) return false;
  }
  return true;
}

void check_catalog(const std::vector<SynthMaterial>& catalog) {
  std::set<std::string> names;
  for (const SynthMaterial& m : catalog) {
    if (!plain_file_name(m.name))
      throw Error("synthetic material name '" + m.name +
                  "' is not a plain file name (letters, digits, '.', '-', '_')");
    if (!names.insert(m.name).second) throw Error("two synthetic materials are named '" + m.name + "'");
    try {
      validate(m.brdf);
    } catch (const Error& e) {
      throw Error("synthetic material '" + m.name + "': " + e.what());
    }
  }
}

void make_folder(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw file_error(dir, "cannot create the output folder: " + ec.message());
  if (!fs::is_directory(dir, ec)) throw file_error(dir, "exists and is not a folder");
}

}  // namespace

std::vector<fs::path> write_database(const fs::path& dir, const std::vector<SynthMaterial>& catalog,
                                     ProgressSink& progress, MerlDims dims) {
  check_catalog(catalog);
  make_folder(dir);
  std::vector<fs::path> written;
  written.reserve(catalog.size());
  ProgressTask task(progress, "synthesising BRDFs", catalog.size());
  for (const SynthMaterial& m : catalog) {
    const BrdfTable table = tabulate([&m](const Vec3& wi, const Vec3& wo) { return evaluate(m.brdf, wi, wo); }, dims);
    const fs::path path = dir / m.file_name();
    write_merl(path, table, /*allow_nonstandard_dims=*/!dims.is_standard());
    written.push_back(path);
    task.advance();
  }
  return written;
}

}  // namespace matlas
