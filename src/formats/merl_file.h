#pragma once
// MERL `.binary` BRDF files: int32 header (theta_h, theta_d, phi_d bin counts, little-endian),
// then 3 * bins float64 values in stored units: red block, green block, blue block.
//
// Every error is a matlas::Error naming the file: missing, a directory, empty or truncated, size
// not matching the header, negative or absurd dims, NaN, infinite or absurdly large values
// (beyond kMaxMerlMagnitude), not a regular file (a FIFO, a device).
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "brdf/brdf_table.h"
#include "core/direct_reader.h"

namespace matlas {

/// An open, validated MERL file from which ranges of values can be read (streaming ingestion).
class MerlFile {
public:
  explicit MerlFile(std::filesystem::path path);
  MerlFile(MerlFile&& other) noexcept;
  MerlFile& operator=(MerlFile&& other) noexcept;
  MerlFile(const MerlFile&) = delete;
  MerlFile& operator=(const MerlFile&) = delete;
  ~MerlFile();

  /// A table converted in memory (an RGL .bsdf resampled onto the MERL grid), served through the
  /// same streaming interface from an unlinked temporary file in the system temporary folder (so
  /// that a large database costs disk cache, not memory). `path` is the source, named in errors.
  static MerlFile from_table(std::filesystem::path path, const BrdfTable& table);

  const std::filesystem::path& path() const { return path_; }
  const MerlDims& dims() const { return dims_; }
  /// 3 * bins.
  std::size_t value_count() const { return 3 * dims_.bins(); }
  static constexpr std::size_t kHeaderBytes = 12;

  /// Reads values [first, first + count) in stored units (negative = missing). Throws if a value
  /// is NaN, infinite or beyond kMaxMerlMagnitude, naming the file and the value's channel and bin.
  void read_values(std::size_t first, std::size_t count, double* out) const;

  /// Asks the kernel to start reading values [first, first + count) from disk in the background
  /// (posix_fadvise WILLNEED), so that a later read finds them in the page cache. Advisory.
  void prefetch(std::size_t first, std::size_t count) const;
  /// Tells the kernel that values [first, first + count) will not be read again, so that their
  /// pages leave the page cache first (posix_fadvise DONTNEED). Advisory.
  void release(std::size_t first, std::size_t count) const;

  /// A reader of this file's bytes around the page cache (core/direct_reader.h), for a pass over a
  /// database larger than memory; it reads the bytes of values [first, first + count) from
  /// value_offset(first). The file must outlive it.
  DirectReader direct_reader() const { return DirectReader(fd_, path_); }
  static constexpr std::uint64_t value_offset(std::size_t first) { return kHeaderBytes + first * sizeof(double); }
  /// Throws, as read_values does, when one of `count` values read from value index `first` (their
  /// stored bytes, at any alignment) is NaN, infinite or beyond kMaxMerlMagnitude.
  void check(std::size_t first, const std::byte* values, std::size_t count) const;

  /// Values per chunk of visit_values (64 KiB: the chunk stays in L1/L2 while visited).
  static constexpr std::size_t kVisitChunk = 8192;
  /// Reads values [first, first + count) through a small cache-resident buffer and calls
  /// visit(chunk, offset, length) for consecutive chunks (offset counted from `first`): the stored
  /// bytes of `length` values, each already checked for NaN and infinities (same errors as
  /// read_values). For callers that transform the values anyway: the kernel copies into a buffer
  /// that stays in cache, and the caller's single pass writes the destination, instead of a copy
  /// into a large destination followed by passes over it.
  template <class Visit>
  void visit_values(std::size_t first, std::size_t count, Visit&& visit) const {
    check_range(first, count);
    thread_local double buffer[kVisitChunk];
    for (std::size_t done = 0; done < count; done += kVisitChunk) {
      const std::size_t n = count - done < kVisitChunk ? count - done : kVisitChunk;
      read_checked(first + done, n, buffer);
      visit(reinterpret_cast<const std::byte*>(buffer), done, n);
    }
  }
  /// The same for values [first, first + count) whose stored bytes were read elsewhere (a
  /// BlockPrefetch) and may have any alignment: each chunk is checked, then visited in place (the
  /// visitor loads the values with memcpy, so no copy is made).
  template <class Visit>
  void visit_bytes(const std::byte* bytes, std::size_t first, std::size_t count, Visit&& visit) const {
    check_range(first, count);
    for (std::size_t done = 0; done < count; done += kVisitChunk) {
      const std::size_t n = count - done < kVisitChunk ? count - done : kVisitChunk;
      const std::byte* chunk = bytes + done * sizeof(double);
      check(first + done, chunk, n);
      visit(chunk, done, n);
    }
  }

private:
  MerlFile() = default;
  /// Throws (internal error) when [first, first + count) is not inside the table.
  void check_range(std::size_t first, std::size_t count) const;
  /// posix_fadvise(advice) on the bytes of values [first, first + count), clipped to the table.
  void advise(std::size_t first, std::size_t count, int advice) const;
  /// One read of values [first, first + count) into out, then the NaN/Inf check.
  void read_checked(std::size_t first, std::size_t count, double* out) const;

  std::filesystem::path path_;
  MerlDims dims_{};
  int fd_ = -1;
};

/// Reads a whole MERL file.
BrdfTable read_merl(const std::filesystem::path& path);

/// Writes a MERL file atomically. Files meant for other tools must have the standard 90x90x180
/// grid: other dims are refused unless allow_nonstandard_dims is set. A table holding a value
/// read_merl refuses (NaN, infinite, beyond kMaxMerlMagnitude) is refused, nothing written.
void write_merl(const std::filesystem::path& path, const BrdfTable& table,
                bool allow_nonstandard_dims = false);

/// The bytes of the MERL file of `table`, in memory (for downloads): exactly what write_merl
/// writes (any dims; write_merl's check for the standard grid is the caller's business).
std::string encode_merl(const BrdfTable& table);

/// A table from the bytes of a MERL file in memory (uploads), checked exactly as read_merl checks
/// a file; errors are matlas::Error naming `name` (what the bytes are, e.g. "the upload").
BrdfTable decode_merl(std::string_view bytes, const std::filesystem::path& name);

/// Largest bin count accepted per dimension (MERL uses at most 180).
inline constexpr int kMaxMerlDim = 4096;

/// Largest magnitude accepted for a stored value: measured MERL files stay far below (chrome's
/// specular peak is about 4e6 in stored units, 2.7e3 in physical units; the sharpest realistic
/// material we know, the RGL fit cc_blue_agat, peaks at 1.3e9 stored, 8.8e5 physical); a larger
/// value is a corrupted file, and would overflow the squared sums of a build or a projection
/// (1e15 squared times 1e8 values is still far below the double range).
inline constexpr double kMaxMerlMagnitude = 1e15;

}  // namespace matlas
