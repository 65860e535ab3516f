#include "formats/safetensors.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include <nlohmann/json.hpp>

#include "core/check.h"
#include "core/error.h"
#include "core/file_io.h"

namespace matlas {

namespace fs = std::filesystem;
using nlohmann::json;

static_assert(std::endian::native == std::endian::little, "matlas assumes a little-endian host");

namespace {
constexpr std::size_t kAlignment = 64;
constexpr std::uint64_t kMaxHeaderBytes = 100u << 20;

/// Header length (at least `bytes`) that makes the data buffer after "length + header" aligned.
std::size_t aligned_header_size(std::size_t bytes) {
  return (8 + bytes + kAlignment - 1) / kAlignment * kAlignment - 8;
}
}  // namespace

std::size_t dtype_size(DType t) {
  switch (t) {
    case DType::F64: case DType::I64: return 8;
    case DType::F32: case DType::I32: return 4;
    case DType::F16: return 2;
    case DType::U8: return 1;
  }
  return 0;
}

const char* dtype_name(DType t) {
  switch (t) {
    case DType::F64: return "F64";
    case DType::F32: return "F32";
    case DType::F16: return "F16";
    case DType::I32: return "I32";
    case DType::I64: return "I64";
    case DType::U8: return "U8";
  }
  return "?";
}

std::optional<DType> dtype_from_name(const std::string& name) {
  for (DType t : {DType::F64, DType::F32, DType::F16, DType::I32, DType::I64, DType::U8})
    if (name == dtype_name(t)) return t;
  return std::nullopt;
}

std::size_t TensorInfo::elements() const {
  std::size_t n = 1;
  for (auto d : shape) n *= static_cast<std::size_t>(d);
  return n;
}

// ---------------------------------------------------------------- writer

void SafetensorsWriter::add_metadata(const std::string& key, const std::string& value) {
  MATLAS_CHECK(!file_ || reserved_ != 0, "metadata after begin");
  metadata_[key] = value;
}

void SafetensorsWriter::declare(const std::string& name, DType dtype, std::vector<std::int64_t> shape) {
  MATLAS_CHECK(!file_, "declare after begin");
  MATLAS_CHECK(!has_growing(), "fixed tensor '" + name + "' declared after a growing one");
  TensorInfo t;
  t.name = name;
  t.dtype = dtype;
  t.shape = std::move(shape);
  t.begin = expected_;
  t.end = expected_ + t.elements() * dtype_size(dtype);
  expected_ = t.end;
  tensors_.push_back(std::move(t));
  growing_.push_back(false);
  done_.push_back(false);
}

void SafetensorsWriter::declare_growing(const std::string& name, DType dtype, std::vector<std::int64_t> row_shape) {
  MATLAS_CHECK(!file_, "declare after begin");
  TensorInfo t;
  t.name = name;
  t.dtype = dtype;
  t.shape = std::move(row_shape);
  t.shape.insert(t.shape.begin(), 0);
  tensors_.push_back(std::move(t));
  growing_.push_back(true);
  done_.push_back(false);
}

std::string SafetensorsWriter::header_text() const {
  json header = json::object();
  for (const auto& t : tensors_)
    header[t.name] = {{"dtype", dtype_name(t.dtype)}, {"shape", t.shape}, {"data_offsets", {t.begin, t.end}}};
  if (!metadata_.empty()) header["__metadata__"] = metadata_;
  return header.dump();
}

TensorInfo& SafetensorsWriter::tensor(const std::string& name) {
  for (auto& t : tensors_)
    if (t.name == name) return t;
  check_failed(__FILE__, __LINE__, "tensor declared", "no tensor '" + name + "'");
}

void SafetensorsWriter::begin(const fs::path& path) {
  MATLAS_CHECK(!has_growing(), "growing tensors need a reserved header");
  std::string text = header_text();
  text.resize(aligned_header_size(text.size()), ' ');
  file_ = std::make_unique<AtomicFile>(path);
  const std::uint64_t length = text.size();
  file_->write(&length, 8);
  file_->write(text);
}

void SafetensorsWriter::begin(const fs::path& path, std::size_t reserved_header_bytes) {
  reserved_ = aligned_header_size(std::max<std::size_t>(reserved_header_bytes, 2));
  file_ = std::make_unique<AtomicFile>(path);
  // The header and the fixed tensors are filled in by write_tensor() and commit(); growing
  // tensors are appended after them.
  file_->skip(8 + reserved_ + expected_);
  file_->stream_appends_to_disk();
  current_growing_ = 0;
  while (current_growing_ < tensors_.size() && !growing_[current_growing_]) ++current_growing_;
  growing_end_ = expected_;
  if (current_growing_ < tensors_.size()) tensors_[current_growing_].begin = growing_end_;
}

void SafetensorsWriter::write(const void* data, std::size_t bytes) {
  MATLAS_CHECK(file_, "write before begin");
  MATLAS_CHECK(!reserved_, "write in reserved-header mode");
  MATLAS_CHECK_LE(written_ + bytes, expected_);
  file_->write(data, bytes);
  written_ += bytes;
}

void SafetensorsWriter::write_tensor(const std::string& name, const void* data, std::size_t bytes) {
  MATLAS_CHECK(file_ && reserved_, "write_tensor needs begin(path, reserved)");
  TensorInfo& t = tensor(name);
  const auto index = static_cast<std::size_t>(&t - tensors_.data());
  MATLAS_CHECK(!growing_[index], "tensor '" + name + "' is growing");
  MATLAS_CHECK_EQ(bytes, t.bytes());
  file_->write_at(8 + reserved_ + t.begin, data, bytes);
  if (!done_[index]) written_ += bytes;
  done_[index] = true;
}

void SafetensorsWriter::append(const void* data, std::size_t bytes) {
  MATLAS_CHECK(file_ && reserved_ && current_growing_ < tensors_.size(), "append without an open growing tensor");
  if (data) file_->write(data, bytes);
  else file_->skip(bytes);  // skip(): written by another process
  growing_end_ += bytes;
}

void SafetensorsWriter::skip(std::size_t bytes) { append(nullptr, bytes); }

std::uint64_t SafetensorsWriter::append_offset() const { return 8 + reserved_ + growing_end_; }

std::uint64_t SafetensorsWriter::tensor_offset(const std::string& name) { return 8 + reserved_ + tensor(name).begin; }

void SafetensorsWriter::written_elsewhere(const std::string& name) {
  TensorInfo& t = tensor(name);
  const auto index = static_cast<std::size_t>(&t - tensors_.data());
  MATLAS_CHECK(file_ && reserved_ && !growing_[index], "'" + name + "' is growing or not begun");
  if (!done_[index]) written_ += t.bytes();
  done_[index] = true;
}

const fs::path& SafetensorsWriter::temporary() const {
  MATLAS_CHECK(file_, "temporary before begin");
  return file_->temporary();
}

void SafetensorsWriter::end_growing() {
  MATLAS_CHECK(file_ && current_growing_ < tensors_.size(), "end_growing without an open growing tensor");
  TensorInfo& t = tensors_[current_growing_];
  std::size_t row_bytes = dtype_size(t.dtype);
  for (std::size_t k = 1; k < t.shape.size(); ++k) row_bytes *= static_cast<std::size_t>(t.shape[k]);
  const std::size_t bytes = growing_end_ - t.begin;
  MATLAS_CHECK(row_bytes != 0 && bytes % row_bytes == 0, "tensor '" + t.name + "' has a partial row");
  t.shape[0] = static_cast<std::int64_t>(bytes / row_bytes);
  t.end = growing_end_;
  done_[current_growing_] = true;
  ++current_growing_;
  if (current_growing_ < tensors_.size()) tensors_[current_growing_].begin = growing_end_;
}

void SafetensorsWriter::commit() {
  MATLAS_CHECK(file_, "commit before begin");
  MATLAS_CHECK_EQ(written_, expected_);
  if (reserved_) {
    for (std::size_t k = 0; k < tensors_.size(); ++k)
      MATLAS_CHECK(done_[k], "tensor '" + tensors_[k].name + "' not written");
    std::string text = header_text();
    MATLAS_CHECK_LE(text.size(), reserved_);
    text.resize(reserved_, ' ');
    const std::uint64_t length = text.size();
    std::string head(reinterpret_cast<const char*>(&length), 8);
    head += text;
    file_->write_at(0, head.data(), head.size());
  }
  file_->commit();
}

// ---------------------------------------------------------------- reader

namespace {

/// One tensor's entry of the header, checked against the data buffer's size (`buffer` bytes).
/// json::exception for a missing key or a value of another type (the caller names the file).
TensorInfo parse_tensor(const fs::path& path, const std::string& name, const json& entry, std::size_t buffer) {
  TensorInfo t;
  t.name = name;
  const auto dtype = dtype_from_name(entry.at("dtype").get<std::string>());
  if (!dtype) throw file_error(path, "tensor '" + t.name + "' has an unsupported dtype");
  t.dtype = *dtype;
  // Integers only: nlohmann converts a float such as 2e34 to an integer type by a cast that
  // is undefined out of range (UBSan: "outside the range of representable values"), and a
  // float in range (8.0) would pass for an integer.
  const json& shape = entry.at("shape");
  const json& offset_list = entry.at("data_offsets");
  if (!shape.is_array() || !std::all_of(shape.begin(), shape.end(), [](const json& d) { return d.is_number_integer(); }))
    throw file_error(path, "tensor '" + t.name + "': its shape is not a list of integers (corrupted header)");
  if (!offset_list.is_array() ||
      !std::all_of(offset_list.begin(), offset_list.end(), [](const json& d) { return d.is_number_unsigned(); }))
    throw file_error(path, "tensor '" + t.name + "': its data offsets are not non-negative integers (corrupted header)");
  t.shape = shape.get<std::vector<std::int64_t>>();
  const auto offsets = offset_list.get<std::vector<std::size_t>>();
  if (offsets.size() != 2 || offsets[0] > offsets[1])
    throw file_error(path, "tensor '" + t.name + "' has invalid data offsets");
  t.begin = offsets[0];
  t.end = offsets[1];
  // The byte size is computed with overflow checks: a crafted shape whose product wraps
  // around must not pass for the real size (and later ask for absurd allocations).
  std::size_t bytes = dtype_size(t.dtype);
  for (auto d : t.shape) {
    if (d < 0) throw file_error(path, "tensor '" + t.name + "' has a negative dimension");
    if (__builtin_mul_overflow(bytes, static_cast<std::size_t>(d), &bytes))
      throw file_error(path, "tensor '" + t.name + "': its shape overflows (corrupted header)");
  }
  if (bytes != t.bytes())
    throw file_error(path, "tensor '" + t.name + "': shape and byte size disagree (corrupted header)");
  if (t.end > buffer)
    throw file_error(path, "truncated: tensor '" + t.name + "' ends at byte " +
                               std::to_string(t.end) + " of a " + std::to_string(buffer) +
                               "-byte data buffer");
  return t;
}

}  // namespace

SafetensorsFile SafetensorsFile::open(const fs::path& path) {
  SafetensorsFile f;
  f.map_ = std::make_shared<MappedFile>(path);
  const std::size_t size = f.map_->size();
  if (size == 0) throw file_error(path, "empty file");
  if (size < 8) throw file_error(path, "truncated: too short for a safetensors header");
  std::uint64_t length = 0;
  std::memcpy(&length, f.map_->data(), 8);
  if (length < 2 || length > kMaxHeaderBytes)
    throw file_error(path, "not a safetensors file (header length " + std::to_string(length) + ")");
  if (8 + length > size)
    throw file_error(path, "truncated: header says " + std::to_string(length) +
                               " bytes but the file has " + std::to_string(size));
  const char* text = reinterpret_cast<const char*>(f.map_->data() + 8);
  json header;
  try {
    header = json::parse(text, text + length);
  } catch (const json::exception& e) {
    throw file_error(path, std::string("not a safetensors file (header is not JSON: ") + e.what() + ")");
  }
  if (!header.is_object()) throw file_error(path, "not a safetensors file (header is not an object)");
  f.data_ = f.map_->data() + 8 + length;
  const std::size_t buffer = size - 8 - length;
  try {
    for (auto it = header.begin(); it != header.end(); ++it) {
      if (it.key() == "__metadata__") {
        for (auto m = it->begin(); m != it->end(); ++m) f.metadata_[m.key()] = m->get<std::string>();
        continue;
      }
      f.tensors_.push_back(parse_tensor(path, it.key(), *it, buffer));
    }
  } catch (const json::exception& e) {
    throw file_error(path, std::string("corrupted safetensors header: ") + e.what());
  }
  std::sort(f.tensors_.begin(), f.tensors_.end(),
            [](const TensorInfo& a, const TensorInfo& b) { return a.begin < b.begin; });
  std::size_t cursor = 0;
  for (const auto& t : f.tensors_) {
    if (t.begin != cursor)
      throw file_error(path, "corrupted safetensors header: tensor '" + t.name + "' overlaps or leaves a hole");
    cursor = t.end;
  }
  if (cursor != buffer)
    throw file_error(path, "size mismatch: " + std::to_string(buffer - cursor) +
                               " unexpected bytes after the last tensor");
  return f;
}

const TensorInfo* SafetensorsFile::find(const std::string& name) const {
  for (const auto& t : tensors_)
    if (t.name == name) return &t;
  return nullptr;
}

const TensorInfo& SafetensorsFile::require(const std::string& name, DType dtype,
                                           const std::vector<std::int64_t>& shape) const {
  const TensorInfo* t = find(name);
  if (!t) throw file_error(path(), "missing tensor '" + name + "'");
  if (t->dtype != dtype)
    throw file_error(path(), "tensor '" + name + "' is " + dtype_name(t->dtype) + ", expected " +
                                 dtype_name(dtype));
  if (!shape.empty() && t->shape != shape)
    throw file_error(path(), "tensor '" + name + "' has an unexpected shape");
  return *t;
}

}  // namespace matlas
