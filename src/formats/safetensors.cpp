#include "formats/safetensors.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <mutex>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_io.h"
#include "formats/mapping_watch.h"

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
  if (file_ && reserved_ == 0) throw Error("SafetensorsWriter: metadata after begin (internal error)");
  metadata_[key] = value;
}

void SafetensorsWriter::declare(const std::string& name, DType dtype, std::vector<std::int64_t> shape) {
  if (file_) throw Error("SafetensorsWriter: declare after begin (internal error)");
  if (has_growing())
    throw Error("SafetensorsWriter: fixed tensor '" + name + "' declared after a growing one (internal error)");
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
  if (file_) throw Error("SafetensorsWriter: declare after begin (internal error)");
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
  throw Error("SafetensorsWriter: no tensor '" + name + "' declared (internal error)");
}

void SafetensorsWriter::begin(const fs::path& path) {
  if (has_growing())
    throw Error("SafetensorsWriter: growing tensors need a reserved header (internal error)");
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
  if (!file_) throw Error("SafetensorsWriter::write before begin (internal error)");
  if (reserved_) throw Error("SafetensorsWriter::write in reserved-header mode (internal error)");
  if (written_ + bytes > expected_)
    throw file_error(file_->target(), "more tensor data than declared (internal error)");
  file_->write(data, bytes);
  written_ += bytes;
}

void SafetensorsWriter::write_tensor(const std::string& name, const void* data, std::size_t bytes) {
  if (!file_ || !reserved_) throw Error("SafetensorsWriter::write_tensor needs begin(path, reserved) (internal error)");
  TensorInfo& t = tensor(name);
  const auto index = static_cast<std::size_t>(&t - tensors_.data());
  if (growing_[index] || bytes != t.bytes())
    throw file_error(file_->target(), "tensor '" + name + "' written with " + std::to_string(bytes) + " bytes, declared " +
                                          std::to_string(t.bytes()) + " (internal error)");
  file_->write_at(8 + reserved_ + t.begin, data, bytes);
  if (!done_[index]) written_ += bytes;
  done_[index] = true;
}

void SafetensorsWriter::append(const void* data, std::size_t bytes) {
  if (!file_ || !reserved_ || current_growing_ >= tensors_.size())
    throw Error("SafetensorsWriter::append without an open growing tensor (internal error)");
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
  if (!file_ || !reserved_ || growing_[index])
    throw Error("SafetensorsWriter::written_elsewhere: '" + name + "' is growing or not begun (internal error)");
  if (!done_[index]) written_ += t.bytes();
  done_[index] = true;
}

const fs::path& SafetensorsWriter::temporary() const {
  if (!file_) throw Error("SafetensorsWriter::temporary before begin (internal error)");
  return file_->temporary();
}

void SafetensorsWriter::end_growing() {
  if (!file_ || current_growing_ >= tensors_.size())
    throw Error("SafetensorsWriter::end_growing without an open growing tensor (internal error)");
  TensorInfo& t = tensors_[current_growing_];
  std::size_t row_bytes = dtype_size(t.dtype);
  for (std::size_t k = 1; k < t.shape.size(); ++k) row_bytes *= static_cast<std::size_t>(t.shape[k]);
  const std::size_t bytes = growing_end_ - t.begin;
  if (row_bytes == 0 || bytes % row_bytes != 0)
    throw file_error(file_->target(), "tensor '" + t.name + "' has a partial row (internal error)");
  t.shape[0] = static_cast<std::int64_t>(bytes / row_bytes);
  t.end = growing_end_;
  done_[current_growing_] = true;
  ++current_growing_;
  if (current_growing_ < tensors_.size()) tensors_[current_growing_].begin = growing_end_;
}

void SafetensorsWriter::commit() {
  if (!file_) throw Error("SafetensorsWriter::commit before begin (internal error)");
  if (written_ != expected_)
    throw file_error(file_->target(), "incomplete tensor data: " + std::to_string(written_) + " of " +
                                          std::to_string(expected_) + " bytes (internal error)");
  if (reserved_) {
    for (std::size_t k = 0; k < tensors_.size(); ++k)
      if (!done_[k]) throw file_error(file_->target(), "tensor '" + tensors_[k].name + "' not written (internal error)");
    std::string text = header_text();
    if (text.size() > reserved_)
      throw file_error(file_->target(), "header of " + std::to_string(text.size()) + " bytes exceeds the " +
                                            std::to_string(reserved_) + " reserved (internal error)");
    text.resize(reserved_, ' ');
    const std::uint64_t length = text.size();
    std::string head(reinterpret_cast<const char*>(&length), 8);
    head += text;
    file_->write_at(0, head.data(), head.size());
  }
  file_->commit();
}

// ---------------------------------------------------------------- mapping

namespace {

// SIGBUS guard of the mappings. Fixed slots readable from the signal handler: begin/end of each
// mapping (0 when free) and its fault count.
constexpr int kGuardSlots = 256;
struct GuardSlot {
  std::atomic<std::uintptr_t> begin{0}, end{0};
  std::atomic<std::uint64_t> faults{0};
};
GuardSlot g_guard[kGuardSlots];
struct sigaction g_previous_sigbus {};
std::uintptr_t g_page_size = 4096;

void chain_previous(int sig, siginfo_t* info, void* context) {
  if (g_previous_sigbus.sa_flags & SA_SIGINFO) {
    if (g_previous_sigbus.sa_sigaction) {
      g_previous_sigbus.sa_sigaction(sig, info, context);
      return;
    }
  } else if (g_previous_sigbus.sa_handler != SIG_DFL && g_previous_sigbus.sa_handler != SIG_IGN &&
             g_previous_sigbus.sa_handler != nullptr) {
    g_previous_sigbus.sa_handler(sig);
    return;
  }
  // Default action: restore it and return; the faulting access repeats and ends the process.
  ::signal(SIGBUS, SIG_DFL);
}

void on_sigbus(int sig, siginfo_t* info, void* context) {
  const auto addr = reinterpret_cast<std::uintptr_t>(info->si_addr);
  for (auto& slot : g_guard) {
    const std::uintptr_t begin = slot.begin.load(std::memory_order_acquire);
    if (begin == 0 || addr < begin || addr >= slot.end.load(std::memory_order_acquire)) continue;
    const std::uintptr_t page = g_page_size;
    void* at = reinterpret_cast<void*>(addr & ~(page - 1));
    // A private page of zeros in place of the vanished one: the access is retried and succeeds.
    if (::mmap(at, page, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0) != MAP_FAILED) {
      slot.faults.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    break;
  }
  chain_previous(sig, info, context);
}

void install_sigbus_guard() {
  static std::once_flag once;
  std::call_once(once, [] {
    g_page_size = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    struct sigaction sa {};
    sa.sa_sigaction = on_sigbus;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_SIGINFO | SA_NODEFER;
    ::sigaction(SIGBUS, &sa, &g_previous_sigbus);
  });
}

int guard_mapping(const void* data, std::size_t size) {
  install_sigbus_guard();
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  for (int i = 0; i < kGuardSlots; ++i) {
    std::uintptr_t expected = 0;
    if (g_guard[i].begin.load() != 0) continue;
    // Claim by setting end first (begin stays 0, so the handler ignores the slot until complete).
    if (!g_guard[i].end.compare_exchange_strong(expected, begin + size)) continue;
    g_guard[i].faults.store(0);
    g_guard[i].begin.store(begin, std::memory_order_release);
    return i;
  }
  return -1;  // more than kGuardSlots mappings: this one is unguarded
}

void unguard_mapping(int slot) {
  if (slot < 0) return;
  g_guard[slot].begin.store(0, std::memory_order_release);
  g_guard[slot].end.store(0, std::memory_order_release);
}

std::int64_t mtime_ns(const struct stat& st) {
  return static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
}

}  // namespace

MappedFile::MappedFile(const fs::path& path) : path_(path) {
  const int fd = open_regular_file(path, "a model or safetensors file");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    throw file_error(path, "cannot stat");
  }
  size_ = static_cast<std::size_t>(st.st_size);
  device_ = static_cast<std::uint64_t>(st.st_dev);
  inode_ = static_cast<std::uint64_t>(st.st_ino);
  mtime_ns_ = mtime_ns(st);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      throw file_error(path, std::string("cannot memory-map: ") + std::strerror(errno));
    }
    data_ = static_cast<const std::byte*>(p);
    slot_ = guard_mapping(data_, size_);
  }
  ::close(fd);
  detail::track_mapping(this);
}

MappedFile::~MappedFile() {
  detail::untrack_mapping(this);
  unguard_mapping(slot_);
  if (data_) ::munmap(const_cast<std::byte*>(data_), size_);
}

std::uint64_t MappedFile::faults() const {
  return slot_ >= 0 ? g_guard[slot_].faults.load(std::memory_order_relaxed) : 0;
}

MappedFile::DiskState MappedFile::disk_state() const {
  struct stat st {};
  if (::stat(path_.c_str(), &st) != 0) return DiskState::replaced;
  if (static_cast<std::uint64_t>(st.st_dev) != device_ || static_cast<std::uint64_t>(st.st_ino) != inode_)
    return DiskState::replaced;
  if (static_cast<std::size_t>(st.st_size) != size_ || mtime_ns(st) != mtime_ns_) return DiskState::modified;
  return DiskState::same;
}

// ---------------------------------------------------------------- reader

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
      TensorInfo t;
      t.name = it.key();
      const auto dtype = dtype_from_name(it->at("dtype").get<std::string>());
      if (!dtype) throw file_error(path, "tensor '" + t.name + "' has an unsupported dtype");
      t.dtype = *dtype;
      // Integers only: nlohmann converts a float such as 2e34 to an integer type by a cast that
      // is undefined out of range (UBSan: "outside the range of representable values"), and a
      // float in range (8.0) would pass for an integer.
      const json& shape = it->at("shape");
      const json& offset_list = it->at("data_offsets");
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
      f.tensors_.push_back(std::move(t));
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

// ---------------------------------------------------------------- half floats

std::uint16_t float_to_half(float value) {
  const std::uint32_t f = std::bit_cast<std::uint32_t>(value);
  const std::uint32_t sign = (f >> 16) & 0x8000u;
  const std::uint32_t abs = f & 0x7fffffffu;
  if (abs >= 0x7f800000u)  // Inf or NaN
    return static_cast<std::uint16_t>(sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u));
  if (abs >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // overflow -> Inf
  if (abs < 0x38800000u) {  // subnormal half (or zero)
    const float magnitude = std::bit_cast<float>(abs);
    // Scale so the half subnormal step (2^-24) becomes 1, then round to nearest even.
    const float scaled = magnitude * 16777216.0f;
    const auto rounded = static_cast<std::uint32_t>(std::nearbyint(scaled));
    return static_cast<std::uint16_t>(sign | rounded);
  }
  // Normal: rebias the exponent and round the mantissa to 10 bits, nearest even.
  std::uint32_t h = ((abs - 0x38000000u) >> 13);
  const std::uint32_t rest = abs & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;
  return static_cast<std::uint16_t>(sign | h);
}

float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu;
  const std::uint32_t mantissa = h & 0x3ffu;
  if (exponent == 0) {
    const float magnitude = static_cast<float>(mantissa) * (1.0f / 16777216.0f);
    return sign ? -magnitude : magnitude;
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
  return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

}  // namespace matlas
