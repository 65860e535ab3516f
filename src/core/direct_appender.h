#pragma once
// DirectAppender: streams a large sequential write to disk with direct I/O (O_DIRECT), from a
// background thread that writes the staged buffers in order while the caller fills others.
// Measured here with dd (docs/BENCHMARKS.md): buffered writes of a 1.3 GB file cost 3.4 s of
// kernel CPU time (page-cache allocation and copy) plus 1 s of fsync, direct writes 0.86 s of
// mostly idle waiting. For outputs written once (model files), the appends are thus nearly free
// for the CPU and overlap with the work that produces them.
//
// Direct I/O needs block-aligned offsets, sizes and memory: appends are staged in aligned
// buffers and written in whole buffers; the remainder (less than one buffer) is returned by
// finish() for the caller to write through the page cache.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

namespace matlas {

class DirectAppender {
public:
  /// File offsets, buffer sizes and addresses are multiples of this.
  static constexpr std::size_t kAlignment = 4096;
  static constexpr std::size_t kBufferBytes = 16u << 20;
  /// Staging buffers at most (allocated as the appends need them: 96 MB). A build appends each
  /// block's data at once (49 MB for 1000 materials): with two buffers, the appending thread
  /// waited for the disk twice per block (CHANGELOG.md, thirty-sixth session).
  static constexpr std::size_t kMaxBuffers = 6;

  /// Opens `path` (an existing file) for direct writes starting at `offset` (a multiple of
  /// kAlignment). Returns null where the file system does not support direct I/O, where `path` is
  /// a symlink, and, when `same_file_as` is an open descriptor, where `path` no longer names its
  /// file (the caller then writes through its own descriptor).
  static std::unique_ptr<DirectAppender> open(const std::filesystem::path& path, std::uint64_t offset,
                                              int same_file_as = -1);
  ~DirectAppender();
  DirectAppender(const DirectAppender&) = delete;
  DirectAppender& operator=(const DirectAppender&) = delete;

  /// Appends bytes (copied into the staging buffers; waits only when all kMaxBuffers are full and
  /// queued for the disk). Rethrows an earlier write failure.
  void append(const void* data, std::size_t bytes);
  /// Waits until every full buffer is on disk and returns the staged remainder, which belongs
  /// at tail_offset(). Throws matlas::Error naming the file if a write failed.
  std::span<const std::byte> finish();
  std::uint64_t tail_offset() const;

private:
  struct State;
  explicit DirectAppender(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace matlas
