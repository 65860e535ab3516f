#pragma once
// Fuzz input as a file: an anonymous in-memory file (memfd) reached through /proc/self/fd, so
// that the readers under test open a real regular file without touching the disk.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include <sys/mman.h>
#include <unistd.h>

namespace matlas::fuzz {

class MemFile {
public:
  MemFile(const std::uint8_t* data, std::size_t size) {
    fd_ = ::memfd_create("matlas-fuzz", MFD_CLOEXEC);
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(fd_, data + done, size - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~MemFile() { ::close(fd_); }
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

private:
  int fd_ = -1;
  std::filesystem::path path_;
};

}  // namespace matlas::fuzz
