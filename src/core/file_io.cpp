#include "core/file_io.h"

#include <algorithm>

#include <cerrno>
#include <cstring>
#include <string>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/resource.h>
#include <unistd.h>

#include "core/error.h"

namespace matlas {

void refuse_output_among_inputs(const std::filesystem::path& output,
                                const std::vector<std::filesystem::path>& inputs) {
  if (output.empty()) return;  // AtomicFile names that problem
  struct stat out {};
  const bool out_exists = ::stat(output.c_str(), &out) == 0;
  std::error_code ec;
  const std::filesystem::path out_canonical = std::filesystem::weakly_canonical(output, ec);
  const bool have_canonical = !ec;
  for (const auto& input : inputs) {
    if (input.empty()) continue;
    struct stat in {};
    if (::stat(input.c_str(), &in) != 0) continue;
    bool same = out_exists && in.st_dev == out.st_dev && in.st_ino == out.st_ino;
    if (!same && have_canonical) {
      std::error_code ec_in;
      const std::filesystem::path in_canonical = std::filesystem::weakly_canonical(input, ec_in);
      same = !ec_in && in_canonical == out_canonical;
    }
    if (same)
      throw file_error(output, "the output is one of the inputs (" + input.string() +
                                   "): refusing to overwrite it; choose another output name");
  }
}

std::string file_kind(unsigned mode) {
  switch (mode & S_IFMT) {
    case S_IFREG: return "a regular file";
    case S_IFDIR: return "a directory";
    case S_IFIFO: return "a named pipe (FIFO)";
    case S_IFSOCK: return "a socket";
    case S_IFCHR: return "a character device";
    case S_IFBLK: return "a block device";
    default: return "not a regular file";
  }
}

int open_regular_file(const std::filesystem::path& path, const std::string& expected) {
  if (path.empty()) throw Error("an empty file name was given, expected " + expected);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT) throw file_error(path, "no such file");
    if (err == ELOOP) throw file_error(path, "too many levels of symbolic links (a symlink loop?)");
    throw file_error(path, std::string("cannot open: ") + std::strerror(err));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    ::close(fd);
    throw file_error(path, std::string("cannot stat: ") + std::strerror(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    throw file_error(path, "is " + file_kind(st.st_mode) + ", not " + expected);
  }
  // Regular files ignore O_NONBLOCK, but clear it so that the descriptor behaves as usual.
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

bool allow_open_files(std::size_t count) {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return false;
  if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= count) return true;
  const rlim_t wanted = limit.rlim_max == RLIM_INFINITY ? static_cast<rlim_t>(count)
                                                        : std::min<rlim_t>(limit.rlim_max, static_cast<rlim_t>(count));
  if (wanted <= limit.rlim_cur) return false;
  limit.rlim_cur = wanted;
  return ::setrlimit(RLIMIT_NOFILE, &limit) == 0 && wanted >= count;
}

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
