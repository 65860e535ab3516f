#include "formats/merl_file.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/simd_clones.h"

namespace matlas {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little, "MERL files are little-endian");

namespace {

const char* channel_name(std::size_t c) {
  static const char* names[] = {"red", "green", "blue"};
  return c < 3 ? names[c] : "?";
}

/// Whether one of n values stored at `values` (any alignment) is NaN, infinite or beyond
/// kMaxMerlMagnitude: one compare of |x| per value, or-ed without a branch, so that the loop
/// vectorises (a NaN fails the compare). With `a <= M && a >= -M` GCC kept a scalar loop with a
/// branch per value: 8 % of a build's reading.
MATLAS_SIMD_CLONES bool any_unusable(const std::byte* values, std::size_t n) {
  unsigned bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double v;
    std::memcpy(&v, values + i * sizeof(double), sizeof v);
    bad |= static_cast<unsigned>(!(std::fabs(v) <= kMaxMerlMagnitude));
  }
  return bad != 0;
}

/// Throws unless a file of `size` bytes can hold the header.
void check_header_fits(const fs::path& path, std::uint64_t size) {
  if (size == 0) throw file_error(path, "empty file, expected a MERL .binary BRDF");
  if (size < MerlFile::kHeaderBytes)
    throw file_error(path, "truncated: " + std::to_string(size) + " bytes, shorter than the 12-byte MERL header");
}

/// The dims of a header, checked against the file's size in bytes.
MerlDims checked_dims(const fs::path& path, const std::int32_t header[3], std::uint64_t size) {
  for (int d = 0; d < 3; ++d) {
    if (header[d] <= 0 || header[d] > kMaxMerlDim)
      throw file_error(path, "invalid MERL header: dims " + std::to_string(header[0]) + " " +
                                 std::to_string(header[1]) + " " + std::to_string(header[2]) +
                                 " (each must be in 1.." + std::to_string(kMaxMerlDim) +
                                 "; is this a MERL .binary file?)");
  }
  const MerlDims dims{header[0], header[1], header[2]};
  const std::uint64_t expected = MerlFile::kHeaderBytes + 3 * dims.bins() * sizeof(double);
  if (size != expected)
    throw file_error(path, (size < expected ? "truncated: " : "size mismatch: ") + std::to_string(size) +
                               " bytes, but header " + dims.to_string() + " needs " + std::to_string(expected));
  return dims;
}

/// Throws, naming the first unusable value of chunk[0, n) (values first.. of a table of `dims`).
void check_values(const fs::path& path, const MerlDims& dims, std::size_t first, const std::byte* chunk,
                  std::size_t n) {
  if (!any_unusable(chunk, n)) return;
  for (std::size_t i = 0; i < n; ++i) {
    double v;
    std::memcpy(&v, chunk + i * sizeof(double), sizeof v);
    if (v <= kMaxMerlMagnitude && v >= -kMaxMerlMagnitude) continue;
    const std::size_t index = first + i, bins = dims.bins();
    const std::string where = std::string(" in the ") + channel_name(index / bins) + " channel at bin " +
                              std::to_string(index % bins);
    if (!std::isfinite(v)) throw file_error(path, std::string(std::isnan(v) ? "NaN" : "infinite") + " value" + where);
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    throw file_error(path, std::string("absurd value ") + text + where + " (MERL values stay far below 1e15 in " +
                               "stored units; is the file corrupted or not in MERL units?)");
  }
}

std::array<std::int32_t, 3> header_of(const MerlDims& dims) { return {dims.theta_h, dims.theta_d, dims.phi_d}; }

/// Refuses to write a table that read_merl would refuse (NaN, infinite or beyond
/// kMaxMerlMagnitude), naming the output and the first such value.
void check_writable(const fs::path& path, const BrdfTable& table) {
  const auto values = table.stored();
  if (!any_unusable(reinterpret_cast<const std::byte*>(values.data()), values.size())) return;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::fabs(values[i]) <= kMaxMerlMagnitude) continue;
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", values[i]);
    throw file_error(path, std::string("refusing to write value ") + text + " in the " +
                               channel_name(i / table.dims().bins()) + " channel at bin " +
                               std::to_string(i % table.dims().bins()) +
                               ": MERL files hold finite values within 1e15 in stored units, and readers refuse others");
  }
}

}  // namespace

MerlFile::MerlFile(fs::path path) : path_(std::move(path)) {
  fd_ = open_regular_file(path_, "a MERL .binary file");
  try {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) throw file_error(path_, "cannot stat");
    const auto size = static_cast<std::uint64_t>(st.st_size);
    check_header_fits(path_, size);
    std::int32_t header[3];
    read_exact_at(fd_, path_, header, sizeof header, 0);
    dims_ = checked_dims(path_, header, size);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

MerlFile MerlFile::from_table(fs::path path, const BrdfTable& table) {
  MerlFile file;
  file.path_ = std::move(path);
  file.dims_ = table.dims();
  std::error_code ec;
  fs::path dir = fs::temp_directory_path(ec);
  if (ec) dir = "/tmp";
  file.fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (file.fd_ < 0) {  // file systems without O_TMPFILE: a named file, unlinked at once
    std::string name = (dir / "matlas-table-XXXXXX").string();
    file.fd_ = ::mkostemp(name.data(), O_CLOEXEC);
    if (file.fd_ < 0)
      throw file_error(file.path_, "cannot create a temporary file in " + dir.string() + ": " + std::strerror(errno));
    ::unlink(name.c_str());
  }
  const auto header = header_of(table.dims());
  const fs::path where = dir / "(temporary copy)";
  write_all_at(file.fd_, where, header.data(), kHeaderBytes, 0);
  write_all_at(file.fd_, where, table.stored().data(), table.stored().size() * sizeof(double), kHeaderBytes);
  return file;
}

MerlFile::MerlFile(MerlFile&& other) noexcept
    : path_(std::move(other.path_)), dims_(other.dims_), fd_(other.fd_) {
  other.fd_ = -1;
}

MerlFile& MerlFile::operator=(MerlFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    dims_ = other.dims_;
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

MerlFile::~MerlFile() {
  if (fd_ >= 0) ::close(fd_);
}

void MerlFile::read_checked(std::size_t first, std::size_t n, double* chunk) const {
  read_exact_at(fd_, path_, chunk, n * sizeof(double), value_offset(first));
  check_values(path_, dims_, first, reinterpret_cast<const std::byte*>(chunk), n);
}

void MerlFile::check(std::size_t first, const std::byte* values, std::size_t count) const {
  check_values(path_, dims_, first, values, count);
}

void MerlFile::check_range(std::size_t first, std::size_t count) const {
  if (first + count > value_count()) throw file_error(path_, "read past the end of the table (internal error)");
}

void MerlFile::advise(std::size_t first, std::size_t count, int advice) const {
  if (first >= value_count()) return;
  count = std::min(count, value_count() - first);
  ::posix_fadvise(fd_, static_cast<off_t>(value_offset(first)),
                  static_cast<off_t>(count * sizeof(double)), advice);
}

void MerlFile::prefetch(std::size_t first, std::size_t count) const { advise(first, count, POSIX_FADV_WILLNEED); }

void MerlFile::release(std::size_t first, std::size_t count) const { advise(first, count, POSIX_FADV_DONTNEED); }

void MerlFile::read_values(std::size_t first, std::size_t count, double* out) const {
  check_range(first, count);
  // Read in chunks and check each while it is still in cache.
  constexpr std::size_t kChunk = 1 << 17;  // values (1 MiB)
  for (std::size_t done = 0; done < count; done += kChunk)
    read_checked(first + done, std::min(kChunk, count - done), out + done);
}

BrdfTable read_merl(const fs::path& path) {
  MerlFile file(path);
  BrdfTable table(file.dims(), ValueBuffer::Uninitialized{});
  file.read_values(0, table.size(), table.stored().data());
  return table;
}

void write_merl(const fs::path& path, const BrdfTable& table, bool allow_nonstandard_dims) {
  if (path.empty()) throw Error("the output file name is empty");
  if (!allow_nonstandard_dims && !table.dims().is_standard())
    throw file_error(path, "refusing to write a " + table.dims().to_string() +
                               " table: MERL files for other tools are 90x90x180");
  check_writable(path, table);
  const auto header = header_of(table.dims());
  AtomicFile out(path);
  out.write(header.data(), MerlFile::kHeaderBytes);
  out.write(table.stored().data(), table.stored().size() * sizeof(double));
  out.commit();
}

std::string encode_merl(const BrdfTable& table) {
  const auto header = header_of(table.dims());
  const auto values = table.stored();
  std::string bytes(MerlFile::kHeaderBytes + values.size() * sizeof(double), '\0');
  std::memcpy(bytes.data(), header.data(), MerlFile::kHeaderBytes);
  std::memcpy(bytes.data() + MerlFile::kHeaderBytes, values.data(), values.size() * sizeof(double));
  return bytes;
}

BrdfTable decode_merl(std::string_view bytes, const fs::path& name) {
  check_header_fits(name, bytes.size());
  std::int32_t header[3];
  std::memcpy(header, bytes.data(), sizeof header);
  const MerlDims dims = checked_dims(name, header, bytes.size());
  BrdfTable table(dims, ValueBuffer::Uninitialized{});
  std::memcpy(table.stored().data(), bytes.data() + MerlFile::kHeaderBytes, table.size() * sizeof(double));
  check_values(name, dims, 0, reinterpret_cast<const std::byte*>(table.stored().data()), table.size());
  return table;
}

}  // namespace matlas
