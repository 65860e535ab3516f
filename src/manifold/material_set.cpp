#include "manifold/material_set.h"

#include <algorithm>
#include <memory>
#include <set>

#include "core/error.h"
#include "core/file_io.h"
#include "formats/rgl_bsdf.h"

namespace matlas {

namespace fs = std::filesystem;

std::size_t MaterialSet::resampled_count() const {
  return static_cast<std::size_t>(std::count(resampled_.begin(), resampled_.end(), true));
}

MaterialSet MaterialSet::open(const std::vector<fs::path>& inputs, ProgressSink& progress, std::size_t minimum) {
  MaterialSet set;
  std::vector<fs::path> files;
  for (const auto& input : inputs) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      std::vector<fs::path> found;
      // Every step with an error code: a symlink loop or an unreadable entry is reported with its
      // name instead of escaping as a filesystem exception.
      fs::directory_iterator it(input, ec);
      if (ec) throw file_error(input, "cannot list this folder: " + ec.message());
      for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) throw file_error(input, "cannot list this folder: " + ec.message());
        const fs::path& path = it->path();
        // `.binary` entries are inputs whatever they are: MerlFile refuses (with a clear message)
        // a FIFO, a directory or a dangling or looping symlink rather than skipping it silently.
        if (path.extension() == ".binary" || is_rgl_path(path))
          found.push_back(path);
        else
          set.ignored_.push_back(path);
      }
      if (found.empty()) throw file_error(input, "no MERL .binary or RGL .bsdf files in this folder");
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else {
      files.push_back(input);  // MerlFile reports missing or invalid files
    }
  }
  // A descriptor per file, and room for what the commands open besides (outputs, libraries).
  allow_open_files(files.size() + 256);
  std::set<std::string> seen;
  const auto rgl_count = static_cast<std::uint64_t>(std::count_if(files.begin(), files.end(), is_rgl_path));
  std::unique_ptr<ProgressTask> task;
  if (rgl_count) task = std::make_unique<ProgressTask>(progress, "resampling RGL .bsdf files", rgl_count);
  for (const auto& path : files) {
    const bool rgl = is_rgl_path(path);
    MerlFile file = rgl ? MerlFile::from_table(path, resample_to_merl(RglBsdf::read(path))) : MerlFile(path);
    if (rgl) task->advance();
    if (set.files_.empty()) {
      set.dims_ = file.dims();
    } else if (file.dims() != set.dims_) {
      throw file_error(path, "grid " + file.dims().to_string() + " differs from " +
                                 set.files_.front().path().string() + "'s " + set.dims_.to_string() +
                                 ": all materials must share one grid");
    }
    std::string name = path.stem().string();
    if (!seen.insert(name).second)
      throw file_error(path, "duplicate material name '" + name + "' (two inputs with the same file name, "
                             "whatever the extension)");
    set.names_.push_back(std::move(name));
    set.resampled_.push_back(rgl);
    set.files_.push_back(std::move(file));
  }
  if (set.files_.size() < minimum)
    throw Error("need at least " + std::to_string(minimum) +
                (minimum == 1 ? " material" : " materials to build a manifold") + ", found " +
                std::to_string(set.files_.size()));
  return set;
}

void MaterialSet::prefetch(std::size_t first, std::size_t count) const {
  for (const MerlFile& f : files_) f.prefetch(first, count);
}

void MaterialSet::release(std::size_t first, std::size_t count) const {
  for (const MerlFile& f : files_) f.release(first, count);
}

}  // namespace matlas
