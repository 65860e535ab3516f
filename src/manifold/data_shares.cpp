#include "manifold/data_shares.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/file_io.h"

namespace matlas {

namespace fs = std::filesystem;

namespace {

/// Closes a descriptor at the end of a scope.
struct FdGuard {
  int fd;
  ~FdGuard() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

fs::path data_share_path(const fs::path& output, int rank) {
  fs::path p = output;
  p += ".rank-" + std::to_string(rank);
  return p;
}

namespace {

/// Opens the model's temporary file for writing: it exists (rank 0 created it new); never created
/// or followed here.
int open_model(const fs::path& model) {
  const int fd = ::open(model.c_str(), O_WRONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) throw file_error(model, std::string("cannot open for writing: ") + std::strerror(errno));
  return fd;
}

void flush(int fd, const fs::path& model) {
  if (::fsync(fd) != 0) throw file_error(model, std::string("flush failed: ") + std::strerror(errno));
}

}  // namespace

void write_into(const fs::path& model, std::uint64_t offset, const void* data, std::size_t bytes) {
  const FdGuard out{open_model(model)};
  write_all_at(out.fd, model, data, bytes, offset);
  flush(out.fd, model);
}

std::vector<std::byte> read_from(const fs::path& model, std::uint64_t offset, std::size_t bytes) {
  const FdGuard in{open_regular_file(model, "a model being written")};
  std::vector<std::byte> out(bytes);
  read_exact_at(in.fd, model, out.data(), bytes, offset);
  return out;
}

void copy_share_into(const fs::path& share, std::uint64_t bytes, const fs::path& model, std::uint64_t offset) {
  const FdGuard in{open_regular_file(share, "a rank's share of the model data")};
  struct stat st {};
  if (::fstat(in.fd, &st) != 0 || static_cast<std::uint64_t>(st.st_size) != bytes)
    throw file_error(share, "holds " + std::to_string(st.st_size) + " bytes of model data, expected " +
                                std::to_string(bytes));
  const FdGuard out{open_model(model)};
  constexpr std::size_t kChunk = 8u << 20;
  std::vector<char> buffer(static_cast<std::size_t>(std::min<std::uint64_t>(bytes, kChunk)));
  for (std::uint64_t done = 0; done < bytes;) {
    const auto count = static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, bytes - done));
    read_exact_at(in.fd, share, buffer.data(), count, done);
    write_all_at(out.fd, model, buffer.data(), count, offset + done);
    done += count;
  }
  flush(out.fd, model);
}

}  // namespace matlas
