#include "core/direct_reader.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "core/check.h"
#include "core/error.h"
#include "core/file_io.h"

#if defined(__linux__) && !defined(__NR_cachestat)
#define __NR_cachestat 451  // the same number on every architecture (Linux 6.5)
#endif

namespace matlas {

namespace {

std::uint64_t align_down(std::uint64_t x) { return x / DirectReader::kAlignment * DirectReader::kAlignment; }
std::uint64_t align_up(std::uint64_t x) { return align_down(x + DirectReader::kAlignment - 1); }

/// Cleared once a kernel answers that it has no cachestat.
std::atomic<bool> g_cachestat{true};

}  // namespace

DirectReader::DirectReader(int fd, std::filesystem::path name) : fd_(fd), name_(std::move(name)) {
#if defined(__linux__)
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  direct_fd_ = ::open(self.c_str(), O_RDONLY | O_DIRECT | O_CLOEXEC);  // -1: e.g. tmpfs (EINVAL)
#endif
}

DirectReader::~DirectReader() {
  if (direct_fd_ >= 0) ::close(direct_fd_);
}

DirectReader::DirectReader(DirectReader&& other) noexcept
    : fd_(other.fd_), direct_fd_(std::exchange(other.direct_fd_, -1)), name_(std::move(other.name_)) {}

std::size_t DirectReader::span(std::uint64_t offset, std::size_t size) {
  return static_cast<std::size_t>(align_up(offset + size) - align_down(offset));
}

bool DirectReader::cached(std::uint64_t offset, std::size_t size) const {
#if defined(__linux__)
  if (!g_cachestat.load(std::memory_order_relaxed)) return false;
  struct {
    std::uint64_t off, len;
  } range{offset, size};
  struct {
    std::uint64_t nr_cache, nr_dirty, nr_writeback, nr_evicted, nr_recently_evicted;
  } stat{};
  if (::syscall(__NR_cachestat, fd_, &range, &stat, 0) != 0) {
    if (errno == ENOSYS) g_cachestat.store(false, std::memory_order_relaxed);
    return false;
  }
  const std::uint64_t page = static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
  const std::uint64_t pages = (offset + size + page - 1) / page - offset / page;
  return stat.nr_cache >= pages;
#else
  (void)offset;
  (void)size;
  return false;
#endif
}

const std::byte* DirectReader::read(std::uint64_t offset, std::size_t size, std::byte* buffer) const {
  MATLAS_CHECK(reinterpret_cast<std::uintptr_t>(buffer) % kAlignment == 0, "a direct read's buffer is aligned");
  const std::uint64_t begin = align_down(offset), end = align_up(offset + size);
  std::byte* const at = buffer + (offset - begin);
  if (direct_fd_ >= 0 && !cached(offset, size)) {
    // Whole aligned blocks; the file may end inside the last one (a short read there).
    std::uint64_t done = 0;
    while (begin + done < end) {
      const ssize_t got = ::pread(direct_fd_, buffer + done, end - begin - done, static_cast<off_t>(begin + done));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0 && errno == EINVAL) break;  // an alignment this file system refuses: the page cache below
      if (got < 0) throw file_error(name_, std::string("read failed: ") + std::strerror(errno));
      if (got == 0) break;
      done += static_cast<std::uint64_t>(got);
      if (done % kAlignment != 0) break;  // the end of the file (or a short read: the rest below)
    }
    if (begin + done >= offset + size) return at;
    // What is missing through the page cache: it reports a truncated file by name.
    const std::uint64_t have = begin + done > offset ? begin + done - offset : 0;
    read_exact_at(fd_, name_, at + have, size - have, offset + have);
    return at;
  }
  read_exact_at(fd_, name_, at, size, offset);
  return at;
}

}  // namespace matlas
