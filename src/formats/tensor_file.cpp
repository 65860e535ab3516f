#include "formats/tensor_file.h"

#include <algorithm>
#include <cstring>
#include <set>

#include <sys/stat.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"

namespace matlas {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
constexpr std::size_t kMaxRank = 16;
constexpr std::uint32_t kMaxFields = 4096;

/// Thrown by Cursor when the header goes on past the bytes read so far, inside the file.
struct NeedMoreHeader {};

/// Bounds-checked little-endian reader over the first bytes of a file of `file_size` bytes.
class Cursor {
public:
  Cursor(std::span<const std::byte> bytes, std::uint64_t file_size, const fs::path& path)
      : bytes_(bytes), file_size_(file_size), path_(path) {}

  template <class T>
  T get(const char* what) {
    T value;
    need(sizeof value, what);
    std::memcpy(&value, bytes_.data() + pos_, sizeof value);
    pos_ += sizeof value;
    return value;
  }
  std::string string(std::size_t length, const char* what) {
    need(length, what);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), length);
    pos_ += length;
    return s;
  }
  std::size_t position() const { return pos_; }

private:
  void need(std::size_t n, const char* what) const {
    if (bytes_.size() - pos_ >= n) return;
    if (bytes_.size() < file_size_) throw NeedMoreHeader{};
    throw file_error(path_, std::string("truncated tensor file: the header ends inside ") + what + " (" +
                                std::to_string(file_size_) + " bytes)");
  }
  std::span<const std::byte> bytes_;
  std::uint64_t file_size_;
  const fs::path& path_;
  std::size_t pos_ = 0;
};

bool valid_type(std::uint8_t code) { return code >= 1 && code <= 11; }

}  // namespace

std::size_t tensor_type_size(TensorType type) {
  switch (type) {
    case TensorType::UInt8: case TensorType::Int8: return 1;
    case TensorType::UInt16: case TensorType::Int16: case TensorType::Float16: return 2;
    case TensorType::UInt32: case TensorType::Int32: case TensorType::Float32: return 4;
    case TensorType::UInt64: case TensorType::Int64: case TensorType::Float64: return 8;
  }
  return 0;
}

const char* tensor_type_name(TensorType type) {
  switch (type) {
    case TensorType::UInt8: return "uint8";
    case TensorType::Int8: return "int8";
    case TensorType::UInt16: return "uint16";
    case TensorType::Int16: return "int16";
    case TensorType::UInt32: return "uint32";
    case TensorType::Int32: return "int32";
    case TensorType::UInt64: return "uint64";
    case TensorType::Int64: return "int64";
    case TensorType::Float16: return "float16";
    case TensorType::Float32: return "float32";
    case TensorType::Float64: return "float64";
  }
  return "?";
}

std::uint64_t TensorField::count() const {
  std::uint64_t n = 1;
  for (auto s : shape) n *= s;
  return n;
}

std::string TensorField::describe() const {
  std::string s = std::string(tensor_type_name(dtype)) + " [";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

namespace {

/// The header of a tensor file of `file_size` bytes from its first bytes (NeedMoreHeader when
/// they end inside it): the fields without their data, and where each one's data lies, checked
/// against the file's size and against each other.
struct Header {
  std::vector<TensorField> fields;
  std::vector<std::uint64_t> offsets;
};

void check_file_size(std::uint64_t file_size, const fs::path& path) {
  if (file_size == 0) throw file_error(path, "empty file, expected an RGL tensor file (.bsdf)");
  if (file_size > kMaxTensorFileBytes)
    throw file_error(path, std::to_string(file_size) + " bytes: larger than any RGL tensor file (.bsdf) could be (at most " +
                               std::to_string(kMaxTensorFileBytes >> 20) + " MiB are read)");
}

Header parse_header(std::span<const std::byte> bytes, std::uint64_t file_size, const fs::path& path) {
  check_file_size(file_size, path);
  if (bytes.size() < sizeof kMagic && bytes.size() < file_size) throw NeedMoreHeader{};
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw file_error(path, "not a tensor file (the RGL .bsdf format starts with \"tensor_file\")");
  Cursor in(bytes, file_size, path);
  in.string(sizeof kMagic, "the magic");
  const auto major = in.get<std::uint8_t>("the version");
  const auto minor = in.get<std::uint8_t>("the version");
  if (major != 1)
    throw file_error(path, "unsupported tensor file version " + std::to_string(major) + "." + std::to_string(minor) +
                               " (only 1.x is known)");
  const auto count = in.get<std::uint32_t>("the field count");
  if (count == 0 || count > kMaxFields)
    throw file_error(path, "invalid tensor file: " + std::to_string(count) + " fields");

  Header header;
  std::set<std::string> names;
  for (std::uint32_t f = 0; f < count; ++f) {
    TensorField field;
    const auto name_length = in.get<std::uint16_t>("a field name");
    field.name = in.string(name_length, "a field name");
    const std::string label = "field '" + field.name + "'";
    const auto rank = in.get<std::uint16_t>("a field header");
    const auto type = in.get<std::uint8_t>("a field header");
    const auto offset = in.get<std::uint64_t>("a field header");
    if (!valid_type(type))
      throw file_error(path, "invalid tensor file: " + label + " has unknown dtype code " + std::to_string(type));
    if (rank > kMaxRank)
      throw file_error(path, "invalid tensor file: " + label + " has rank " + std::to_string(rank));
    field.dtype = static_cast<TensorType>(type);
    std::uint64_t elements = 1;
    for (std::uint16_t d = 0; d < rank; ++d) {
      const auto extent = in.get<std::uint64_t>("a field shape");
      field.shape.push_back(extent);
      // Bounded by the file's size, not by overflow alone: no extent may exceed what the file
      // holds even where another extent is 0 (a product of 0 must not hide 2^60 x 2^60).
      if (extent > file_size || (extent != 0 && elements > file_size / extent))
        throw file_error(path, "invalid tensor file: " + label + " has an absurd shape " + field.describe() +
                                   " for a file of " + std::to_string(file_size) + " bytes");
      elements *= extent;
    }
    if (!names.insert(field.name).second)
      throw file_error(path, "invalid tensor file: two fields named '" + field.name + "'");
    const std::uint64_t size = elements * tensor_type_size(field.dtype);
    if (offset > file_size || size > file_size - offset)
      throw file_error(path, "truncated: " + label + " (" + field.describe() + ", " + std::to_string(size) +
                                 " bytes at offset " + std::to_string(offset) + ") ends past the end of the file (" +
                                 std::to_string(file_size) + " bytes)");
    header.offsets.push_back(offset);
    header.fields.push_back(std::move(field));
  }
  // Every field's data after the header; together no more than the file holds (fields sharing
  // their bytes would let a small file claim many times its size in memory).
  std::uint64_t total = 0;
  for (std::size_t f = 0; f < header.fields.size(); ++f) {
    const TensorField& field = header.fields[f];
    const std::uint64_t size = field.count() * tensor_type_size(field.dtype);
    if (header.offsets[f] < in.position() && size != 0)
      throw file_error(path, "invalid tensor file: field '" + field.name + "' has its data inside the header");
    total += size;
  }
  if (total > file_size - in.position())
    throw file_error(path, "invalid tensor file: its fields claim " + std::to_string(total) + " bytes of data, more than the " +
                               std::to_string(file_size - in.position()) + " bytes after the header (fields overlap)");
  return header;
}

/// The header's fields with their data, each field's bytes (if any) filled by
/// fill(destination, size, offset in the file).
template <class Fill>
std::vector<TensorField> filled_fields(Header header, Fill&& fill) {
  for (std::size_t f = 0; f < header.fields.size(); ++f) {
    TensorField& field = header.fields[f];
    field.data.resize(field.count() * tensor_type_size(field.dtype));
    if (!field.data.empty()) fill(field.data.data(), field.data.size(), header.offsets[f]);
  }
  return std::move(header.fields);
}

}  // namespace

TensorFile TensorFile::parse(std::span<const std::byte> bytes, const fs::path& path) {
  Header header;
  try {
    header = parse_header(bytes, bytes.size(), path);
  } catch (const NeedMoreHeader&) {
    throw file_error(path, "internal error: the tensor header needs more bytes than the whole file");
  }
  TensorFile file;
  file.path_ = path;
  file.fields_ = filled_fields(std::move(header), [&](std::byte* data, std::size_t size, std::uint64_t offset) {
    std::memcpy(data, bytes.data() + offset, size);
  });
  return file;
}

TensorFile TensorFile::read(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw file_error(path, "is a directory, not an RGL .bsdf file");
  const int fd = open_regular_file(path, "an RGL .bsdf file");
  try {
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw file_error(path, "cannot stat");
    const auto file_size = static_cast<std::uint64_t>(st.st_size);
    check_file_size(file_size, path);
    // The header first (from its first 64 KiB, more only for a header that long), then each
    // field's data straight into its buffer: the file is never held in memory as a whole.
    std::vector<std::byte> prefix;
    Header header;
    for (std::uint64_t want = std::min<std::uint64_t>(file_size, 1 << 16);; want = std::min(file_size, 4 * want)) {
      prefix.resize(static_cast<std::size_t>(want));
      read_exact_at(fd, path, prefix.data(), prefix.size(), 0);
      try {
        header = parse_header(prefix, file_size, path);
        break;
      } catch (const NeedMoreHeader&) {
      }
    }
    prefix = {};
    TensorFile file;
    file.path_ = path;
    file.fields_ = filled_fields(std::move(header), [&](std::byte* data, std::size_t size, std::uint64_t offset) {
      read_exact_at(fd, path, data, size, offset);
    });
    ::close(fd);
    return file;
  } catch (...) {
    ::close(fd);
    throw;
  }
}

void TensorFile::drop_data(const std::string& name) {
  for (auto& f : fields_)
    if (f.name == name) std::vector<std::byte>().swap(f.data);
}

const TensorField* TensorFile::find(const std::string& name) const {
  for (const auto& f : fields_)
    if (f.name == name) return &f;
  return nullptr;
}

const TensorField& TensorFile::field(const std::string& name, const std::string& what) const {
  if (const TensorField* f = find(name)) return *f;
  std::string present;
  for (const auto& f : fields_) present += (present.empty() ? "" : ", ") + f.name;
  throw file_error(path_, "no field '" + name + "' (a " + what + " file needs it; this file has: " + present + ")");
}

std::vector<std::byte> serialize_tensor_file(const std::vector<TensorField>& fields) {
  // Layout first (header, then each field's data 8-byte aligned), then one buffer filled by copies.
  std::size_t header = sizeof kMagic + 2 + 4;
  for (const auto& f : fields) header += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  std::vector<std::uint64_t> offsets;
  std::uint64_t end = (header + 7) / 8 * 8;
  for (const auto& f : fields) {
    offsets.push_back(end);
    end = (end + f.data.size() + 7) / 8 * 8;
  }
  std::vector<std::byte> out(end, std::byte{0});
  std::size_t pos = 0;
  auto put = [&out, &pos](const void* p, std::size_t n) {
    if (n) std::memcpy(out.data() + pos, p, n);
    pos += n;
  };
  put(kMagic, sizeof kMagic);
  const std::uint8_t version[2] = {1, 0};
  put(version, 2);
  const auto count = static_cast<std::uint32_t>(fields.size());
  put(&count, 4);
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const TensorField& f = fields[i];
    const auto name_length = static_cast<std::uint16_t>(f.name.size());
    put(&name_length, 2);
    put(f.name.data(), f.name.size());
    const auto rank = static_cast<std::uint16_t>(f.shape.size());
    put(&rank, 2);
    const auto type = static_cast<std::uint8_t>(f.dtype);
    put(&type, 1);
    put(&offsets[i], 8);
    put(f.shape.data(), 8 * f.shape.size());
  }
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (!fields[i].data.empty()) std::memcpy(out.data() + offsets[i], fields[i].data.data(), fields[i].data.size());
  return out;
}

void write_tensor_file(const fs::path& path, const std::vector<TensorField>& fields) {
  const std::vector<std::byte> bytes = serialize_tensor_file(fields);
  write_file_atomic(path, bytes.data(), bytes.size());
}

TensorField float32_field(std::string name, std::vector<std::uint64_t> shape, std::span<const float> values) {
  TensorField f{std::move(name), TensorType::Float32, std::move(shape), {}};
  if (f.count() != values.size()) throw Error("float32_field '" + f.name + "': shape does not match the values");
  const auto bytes = std::as_bytes(values);
  f.data.assign(bytes.begin(), bytes.end());
  return f;
}

TensorField uint8_field(std::string name, std::vector<std::uint64_t> shape, std::span<const std::uint8_t> values) {
  TensorField f{std::move(name), TensorType::UInt8, std::move(shape), {}};
  if (f.count() != values.size()) throw Error("uint8_field '" + f.name + "': shape does not match the values");
  const auto bytes = std::as_bytes(values);
  f.data.assign(bytes.begin(), bytes.end());
  return f;
}

}  // namespace matlas
