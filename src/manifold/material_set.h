#pragma once
// MaterialSet: the input database of a build. A folder is taken as a user's MERL download is:
// every `*.binary` file in it (sorted by name), other files ignored. All tables must share one
// grid; the material name is the file name without `.binary`.
#include <filesystem>
#include <string>
#include <vector>

#include "formats/merl_file.h"

namespace matlas {

class MaterialSet {
public:
  /// From folders and/or files. Throws matlas::Error naming the offending file for unreadable
  /// files, mixed grids, duplicate names, or when fewer than 2 materials are found.
  static MaterialSet open(const std::vector<std::filesystem::path>& inputs);

  std::size_t size() const { return files_.size(); }
  const MerlDims& dims() const { return dims_; }
  /// Values per material (3 * bins).
  std::size_t value_count() const { return 3 * dims_.bins(); }
  const MerlFile& file(std::size_t i) const { return files_[i]; }
  const std::string& name(std::size_t i) const { return names_[i]; }
  const std::vector<std::string>& names() const { return names_; }
  /// Files that were seen in input folders and skipped (not `.binary`).
  const std::vector<std::filesystem::path>& ignored() const { return ignored_; }

private:
  std::vector<MerlFile> files_;
  std::vector<std::string> names_;
  std::vector<std::filesystem::path> ignored_;
  MerlDims dims_{};
};

}  // namespace matlas
