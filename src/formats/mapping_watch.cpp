#include "formats/mapping_watch.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "core/error.h"
#include "formats/mapped_file.h"

namespace matlas {

namespace {

std::mutex g_mutex;
std::vector<const MappedFile*> g_live;
// Closed mappings that had read zeros, in closing order (rare: a file truncated while mapped).
std::vector<std::pair<std::filesystem::path, std::uint64_t>> g_closed_faulted;

Error truncated_error(const std::filesystem::path& path, std::uint64_t faults) {
  return file_error(path, "the file changed or was truncated while it was read (" + std::to_string(faults) +
                              (faults == 1 ? " page" : " pages") +
                              " of it read as zeros): what was computed from it is wrong and is not written; "
                              "run the command again on the complete file");
}

}  // namespace

namespace detail {

void track_mapping(const MappedFile* file) {
  const std::lock_guard lock(g_mutex);
  g_live.push_back(file);
}

void untrack_mapping(const MappedFile* file) {
  const std::lock_guard lock(g_mutex);
  g_live.erase(std::remove(g_live.begin(), g_live.end(), file), g_live.end());
  if (const std::uint64_t faults = file->faults(); faults > 0) g_closed_faulted.emplace_back(file->path(), faults);
}

}  // namespace detail

MappingFaultWatch::MappingFaultWatch() {
  const std::lock_guard lock(g_mutex);
  closed_at_start_ = g_closed_faulted.size();
}

void MappingFaultWatch::check() const {
  const std::lock_guard lock(g_mutex);
  for (const MappedFile* file : g_live)
    if (const std::uint64_t faults = file->faults(); faults > 0) throw truncated_error(file->path(), faults);
  if (g_closed_faulted.size() > closed_at_start_) {
    const auto& [path, faults] = g_closed_faulted[closed_at_start_];
    throw truncated_error(path, faults);
  }
}

}  // namespace matlas
