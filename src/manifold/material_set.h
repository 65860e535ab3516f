#pragma once
// MaterialSet: the input database of a build. A folder is taken as a user's download is: every
// MERL `*.binary` and RGL `*.bsdf` file in it (sorted by name, both formats may be mixed), other
// files ignored. RGL files are resampled onto the standard MERL grid when the set is opened
// (formats/rgl_bsdf.h); all tables must share one grid. The material name is the file name
// without its extension.
#include <filesystem>
#include <string>
#include <vector>

#include "core/progress.h"
#include "formats/merl_file.h"

namespace matlas {

class MaterialSet {
public:
  /// From folders and/or files. Throws matlas::Error naming the offending file for unreadable
  /// files, anisotropic RGL files, mixed grids, duplicate names, or when fewer than `minimum`
  /// materials are found (2 for a manifold; commands that treat each table on its own, such as
  /// `matlas zonal`, take 1). Resampling RGL files reports to `progress`.
  static MaterialSet open(const std::vector<std::filesystem::path>& inputs,
                          ProgressSink& progress = null_progress(), std::size_t minimum = 2);

  std::size_t size() const { return files_.size(); }
  const MerlDims& dims() const { return dims_; }
  /// Values per material (3 * bins).
  std::size_t value_count() const { return 3 * dims_.bins(); }
  const MerlFile& file(std::size_t i) const { return files_[i]; }
  const std::string& name(std::size_t i) const { return names_[i]; }
  const std::vector<std::string>& names() const { return names_; }
  /// True for a material read from an RGL `.bsdf` file (resampled onto the MERL grid).
  bool resampled(std::size_t i) const { return resampled_[i]; }
  std::size_t resampled_count() const;
  /// MerlFile::prefetch and MerlFile::release of values [first, first + count) of every file: a
  /// streaming pass's requests to the disk (manifold/read_ahead.h). Advisory.
  void prefetch(std::size_t first, std::size_t count) const;
  void release(std::size_t first, std::size_t count) const;
  /// Files that were seen in input folders and skipped (neither `.binary` nor `.bsdf`).
  const std::vector<std::filesystem::path>& ignored() const { return ignored_; }

private:
  std::vector<MerlFile> files_;
  std::vector<std::string> names_;
  std::vector<bool> resampled_;
  std::vector<std::filesystem::path> ignored_;
  MerlDims dims_{};
};

}  // namespace matlas
