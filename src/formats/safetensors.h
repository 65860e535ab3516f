#pragma once
// The safetensors container (https://github.com/huggingface/safetensors): an 8-byte little-endian
// header length N, N bytes of JSON describing each tensor (dtype, shape, [begin, end) byte offsets
// into the data buffer that follows) plus a "__metadata__" map of strings, then the raw
// little-endian tensor data, with no holes. numpy and the `safetensors` Python package read it.
//
// matlas writes the header padded with spaces so that the data buffer starts 64-byte aligned,
// and orders tensors by decreasing element size so every tensor is naturally aligned in a
// memory map.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "formats/mapped_file.h"

namespace matlas {

/// Element types used by matlas.
enum class DType { F64, F32, F16, I32, I64, U8 };
std::size_t dtype_size(DType t);
const char* dtype_name(DType t);
std::optional<DType> dtype_from_name(const std::string& name);

struct TensorInfo {
  std::string name;
  DType dtype = DType::F32;
  std::vector<std::int64_t> shape;
  std::size_t begin = 0, end = 0;  ///< byte offsets into the data buffer
  std::size_t elements() const;
  std::size_t bytes() const { return end - begin; }
};

/// Streaming writer. Two ways to use it:
///  - Everything known up front: declare every tensor and the metadata, begin(path), write the
///    tensors' bytes in declaration order (in as many pieces as convenient), commit().
///  - Sizes or metadata known only at the end (a model build writes its big tensor while it is
///    still computing the small ones): declare the fixed-size tensors, then the growing ones
///    (declare_growing: the first dimension is fixed by the rows appended), begin(path,
///    reserved_header_bytes), then in any order write_tensor() each fixed tensor and append()
///    the growing ones' rows (one growing tensor after the other, end_growing() closing each),
///    add or change metadata, commit(): the header is written into the reserved space (padded
///    with spaces; an error if it does not fit).
/// The file appears at its path only when complete (AtomicFile).
class SafetensorsWriter {
public:
  void add_metadata(const std::string& key, const std::string& value);
  /// Declares a tensor. Tensors are written in the order declared; declare larger element
  /// types first to keep every tensor aligned.
  void declare(const std::string& name, DType dtype, std::vector<std::int64_t> shape);
  /// Declares a tensor of rows of `row_shape` whose count is known at end_growing(). Growing
  /// tensors follow every fixed one in the file, in declaration order.
  void declare_growing(const std::string& name, DType dtype, std::vector<std::int64_t> row_shape);

  /// Creates the file and writes the header.
  void begin(const std::filesystem::path& path);
  /// Creates the file leaving room for a header of up to reserved_header_bytes, written by
  /// commit(). Appended rows go straight to disk (AtomicFile::stream_appends_to_disk).
  void begin(const std::filesystem::path& path, std::size_t reserved_header_bytes);
  /// Appends tensor bytes (in declaration order).
  void write(const void* data, std::size_t bytes);
  template <class T>
  void write(std::span<const T> values) { write(values.data(), values.size_bytes()); }
  /// Writes the whole of a fixed-size tensor at its place (reserved-header mode).
  void write_tensor(const std::string& name, const void* data, std::size_t bytes);
  /// Appends rows to the current growing tensor (reserved-header mode).
  void append(const void* data, std::size_t bytes);
  /// Counts `bytes` of the current growing tensor as appended without writing them: another
  /// process writes them into temporary() at append_offset() (a distributed build's ranks)
  /// before commit().
  void skip(std::size_t bytes);
  /// The file offset of the next appended byte (reserved-header mode, after begin()).
  std::uint64_t append_offset() const;
  /// The file offset of a tensor's first byte (reserved-header mode, after begin(); a growing tensor's once it is
  /// the current one or closed).
  std::uint64_t tensor_offset(const std::string& name);
  /// Counts fixed tensor `name` as written: another process wrote it into temporary() at
  /// tensor_offset(name).
  void written_elsewhere(const std::string& name);
  /// The temporary file being written (renamed into place by commit()).
  const std::filesystem::path& temporary() const;
  /// Closes the current growing tensor: its first dimension is the number of rows appended.
  void end_growing();
  /// Checks that every declared byte was written, then renames the file into place.
  void commit();

private:
  std::string header_text() const;
  bool has_growing() const { return std::find(growing_.begin(), growing_.end(), true) != growing_.end(); }
  TensorInfo& tensor(const std::string& name);

  std::vector<TensorInfo> tensors_;
  std::vector<bool> growing_, done_;
  std::map<std::string, std::string> metadata_;
  std::unique_ptr<AtomicFile> file_;
  std::size_t expected_ = 0, written_ = 0;  ///< bytes of the fixed tensors
  std::size_t reserved_ = 0;                ///< reserved header bytes (0: header written by begin)
  std::size_t current_growing_ = 0;         ///< index of the growing tensor being appended
  std::size_t growing_end_ = 0;             ///< data-buffer offset after the appended rows
};

/// Memory-mapped reader. Validates the whole header on open: errors name the file and say
/// whether it is not a safetensors file, truncated, or inconsistent.
class SafetensorsFile {
public:
  static SafetensorsFile open(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return map_->path(); }
  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  const std::vector<TensorInfo>& tensors() const { return tensors_; }
  const TensorInfo* find(const std::string& name) const;
  /// The tensor's info; throws matlas::Error naming the file if it is absent, has another dtype
  /// or (when `shape` is not empty) another shape.
  const TensorInfo& require(const std::string& name, DType dtype,
                            const std::vector<std::int64_t>& shape = {}) const;
  /// Raw bytes of a tensor.
  const std::byte* bytes(const TensorInfo& t) const { return data_ + t.begin; }
  /// Typed view of a tensor (checks dtype and, if given, shape).
  template <class T>
  std::span<const T> view(const std::string& name, DType dtype,
                          const std::vector<std::int64_t>& shape = {}) const {
    const TensorInfo& t = require(name, dtype, shape);
    return {reinterpret_cast<const T*>(bytes(t)), t.elements()};
  }
  /// Size of the whole file.
  std::size_t file_size() const { return map_->size(); }
  /// The memory map (fault count, state on disk).
  const MappedFile& mapping() const { return *map_; }

private:
  std::shared_ptr<MappedFile> map_;
  const std::byte* data_ = nullptr;
  std::vector<TensorInfo> tensors_;
  std::map<std::string, std::string> metadata_;
};

}  // namespace matlas
