#include "core/file_io.h"

#include <cerrno>
#include <cstring>
#include <string>
#include <unistd.h>

#include "core/error.h"

namespace matlas {

void read_exact_at(int fd, const std::filesystem::path& path, void* out, std::size_t bytes, std::uint64_t offset) {
  auto* dst = static_cast<char*>(out);
  while (bytes > 0) {
    const ssize_t got = ::pread(fd, dst, bytes, static_cast<off_t>(offset));
    if (got < 0) {
      if (errno == EINTR) continue;
      throw file_error(path, std::string("read failed: ") + std::strerror(errno));
    }
    if (got == 0) throw file_error(path, "truncated: unexpected end of file");
    dst += got;
    bytes -= static_cast<std::size_t>(got);
    offset += static_cast<std::uint64_t>(got);
  }
}

void write_all_at(int fd, const std::filesystem::path& path, const void* data, std::size_t bytes,
                  std::uint64_t offset) {
  const auto* src = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t n = ::pwrite(fd, src, bytes, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw file_error(path, std::string("write failed: ") + std::strerror(n < 0 ? errno : EIO));
    src += n;
    bytes -= static_cast<std::size_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
}

}  // namespace matlas
