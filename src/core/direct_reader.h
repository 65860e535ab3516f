#pragma once
// DirectReader: reads byte ranges of an open file around the page cache (O_DIRECT), for passes
// over data larger than memory: through the page cache, a 1000-material build (33 GB on a 23 GB
// machine) added to the cache pages it could not keep, evicting what it had yet to read and what
// other programs had there, and waited on the reads (docs/BENCHMARKS.md, "Direct reads").
//
// A range the page cache already holds in full (cachestat, Linux 6.5 on) is read from the cache
// instead: the device need not read it again (reading it from the device as well gave no faster
// build and tripled the device's traffic after a warm raw read: 36 GB against about 12). Where
// the file system refuses direct I/O (tmpfs) or the kernel has no cachestat, reads fall back to
// the page cache and to the device respectively; the bytes read are the same either way.
#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace matlas {

class DirectReader {
public:
  /// Offsets, sizes and buffer addresses of direct reads are multiples of this.
  static constexpr std::size_t kAlignment = 4096;

  /// For the open file `fd` (not owned; it must outlive the reader), named `name` in errors: a
  /// second descriptor opened for direct reads through /proc/self/fd (so an unlinked file works
  /// too), or none where that is refused.
  DirectReader(int fd, std::filesystem::path name);
  ~DirectReader();
  DirectReader(DirectReader&& other) noexcept;
  DirectReader& operator=(DirectReader&&) = delete;
  DirectReader(const DirectReader&) = delete;
  DirectReader& operator=(const DirectReader&) = delete;

  /// Whether reads can bypass the page cache.
  bool direct() const { return direct_fd_ >= 0; }

  /// Bytes a buffer needs for read(offset, size): the range widened to kAlignment at both ends.
  static std::size_t span(std::uint64_t offset, std::size_t size);
  /// Reads bytes [offset, offset + size) into `buffer` (kAlignment-aligned, span(offset, size)
  /// bytes) and returns where byte `offset` landed in it: from the page cache when it holds them
  /// all, else from the device. Throws matlas::Error naming the file on a read error or when the
  /// file ends before offset + size.
  const std::byte* read(std::uint64_t offset, std::size_t size, std::byte* buffer) const;

private:
  /// Whether the page cache holds every page of the range (false when the kernel cannot tell).
  bool cached(std::uint64_t offset, std::size_t size) const;

  int fd_;
  int direct_fd_ = -1;
  std::filesystem::path name_;
};

}  // namespace matlas
