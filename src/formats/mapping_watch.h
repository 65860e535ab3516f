#pragma once
// Whether the memory-mapped inputs of a computation stayed intact while it read them. A file
// truncated under its MappedFile (formats/safetensors.h) does not kill the process: the vanished
// pages read as zeros and are counted. A result computed from them is wrong (a model point 55-78 %
// off), so a command must not hand it out: the `matlas` command checks a MappingFaultWatch
// before every output file is committed (core/atomic_file.h CommitCheck) and after each command.
#include <cstddef>

namespace matlas {

class MappedFile;

class MappingFaultWatch {
public:
  MappingFaultWatch();
  /// Throws matlas::Error naming the file ("changed or was truncated while it was read") when a
  /// live mapping has read vanished pages as zeros, or a mapping closed since this watch began
  /// had.
  void check() const;

private:
  std::size_t closed_at_start_ = 0;
};

namespace detail {
/// Called by MappedFile: the registry of live mappings (and closed ones that read zeros).
void track_mapping(const MappedFile* file);
void untrack_mapping(const MappedFile* file);
}  // namespace detail

}  // namespace matlas
