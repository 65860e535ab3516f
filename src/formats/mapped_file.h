#pragma once
// A read-only memory map of a whole file that survives the file being truncated under it (the
// SIGBUS guard below); formats/mapping_watch.h tells a command whether any mapping read such pages.
#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace matlas {

/// A read-only memory map of a whole file.
///
/// A mapped file may be truncated or rewritten by another process while it is mapped (a model
/// replaced with `cp` while it is served). Reading a page past the new end of the file raises
/// SIGBUS, which would kill the process: every MappedFile is registered with a SIGBUS handler
/// (installed on first use, chaining to any previous one for other addresses) that maps a page of
/// zeros over the faulting page and counts the fault. Readers then see zeros instead of dying;
/// faults() tells that the content can no longer be trusted, and changed_on_disk() that the file
/// at the path is no longer the one mapped (replaced, truncated or rewritten).
class MappedFile {
public:
  explicit MappedFile(const std::filesystem::path& path);
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();
  const std::byte* data() const { return data_; }
  std::size_t size() const { return size_; }
  const std::filesystem::path& path() const { return path_; }
  /// Pages read past the end of a file truncated while mapped (read as zeros).
  std::uint64_t faults() const;
  /// How the file at path() relates to the mapped one: the same, the same file modified in place
  /// (size or modification time changed: the mapped content is unreliable), or another file
  /// (replaced by rename, or removed: the mapped content is intact).
  enum class DiskState { same, modified, replaced };
  DiskState disk_state() const;

private:
  std::filesystem::path path_;
  const std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  int slot_ = -1;  ///< in the SIGBUS registry
  std::uint64_t device_ = 0, inode_ = 0;
  std::int64_t mtime_ns_ = 0;
};

}  // namespace matlas
