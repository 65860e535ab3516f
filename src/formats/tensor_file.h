#pragma once
// Tensor files: the container of the RGL material database's `.bsdf` files (Dupuy & Jakob 2018),
// as Mitsuba reads it. Little-endian:
//
//   "tensor_file\0"  12 bytes magic
//   u8 major, u8 minor version (1.0)
//   u32 field count
//   per field: u16 name length, name bytes, u16 rank, u8 dtype, u64 data offset, rank x u64 shape
//   field data at their offsets (anywhere after the header, in any order)
//
// dtype codes: 1 u8, 2 i8, 3 u16, 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64.
// Every structural problem (bad magic, truncated header, a field past the end of the file,
// shapes larger than the file, fields sharing bytes, duplicate names, a file over
// kMaxTensorFileBytes) is a matlas::Error naming the file, raised before any field is read.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace matlas {

/// The largest tensor file read (1 GiB; the isotropic RGB files of the RGL database are 0.66 MB):
/// a larger one is refused before anything but its size is looked at.
inline constexpr std::uint64_t kMaxTensorFileBytes = std::uint64_t{1} << 30;

enum class TensorType : std::uint8_t {
  UInt8 = 1, Int8 = 2, UInt16 = 3, Int16 = 4, UInt32 = 5, Int32 = 6, UInt64 = 7, Int64 = 8,
  Float16 = 9, Float32 = 10, Float64 = 11
};

/// Bytes per element of a dtype.
std::size_t tensor_type_size(TensorType type);
/// "float32", "uint8", ...
const char* tensor_type_name(TensorType type);

struct TensorField {
  std::string name;
  TensorType dtype = TensorType::UInt8;
  std::vector<std::uint64_t> shape;
  std::vector<std::byte> data;  ///< count() * element size bytes

  std::uint64_t count() const;
  /// "float32 [8, 128, 128]"
  std::string describe() const;
};

class TensorFile {
public:
  /// Reads and validates a whole tensor file: its header, then each field's data straight into
  /// the field (the file is not held in memory besides).
  static TensorFile read(const std::filesystem::path& path);
  /// Parses a tensor file held in memory; `path` names it in error messages.
  static TensorFile parse(std::span<const std::byte> bytes, const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }
  const std::vector<TensorField>& fields() const { return fields_; }
  /// The field with this name, or nullptr.
  const TensorField* find(const std::string& name) const;
  /// The field with this name; throws "PATH: no field 'NAME' (a FORMAT file has ...)" when absent.
  const TensorField& field(const std::string& name, const std::string& what = "tensor") const;

  void add(TensorField field) { fields_.push_back(std::move(field)); }
  /// Frees the data of the field `name` (its name, type and shape stay): for readers that have
  /// converted it and want the memory back before converting the next one.
  void drop_data(const std::string& name);

private:
  std::filesystem::path path_;
  std::vector<TensorField> fields_;
};

/// Serialises fields as a tensor file (fields in the given order, data 8-byte aligned).
std::vector<std::byte> serialize_tensor_file(const std::vector<TensorField>& fields);
/// Writes a tensor file atomically.
void write_tensor_file(const std::filesystem::path& path, const std::vector<TensorField>& fields);

/// A float32 field from values (for writers and tests).
TensorField float32_field(std::string name, std::vector<std::uint64_t> shape, std::span<const float> values);
/// A uint8 field from bytes.
TensorField uint8_field(std::string name, std::vector<std::uint64_t> shape, std::span<const std::uint8_t> values);

}  // namespace matlas
