#pragma once
// Atomic output: data goes to a temporary file beside the target, which is renamed over the
// target only once it is complete, so a crash or an error never leaves a half-written output.
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>

namespace matlas {

class AtomicFile {
public:
  /// Opens "TARGET.tmp-PID" for writing; throws matlas::Error naming TARGET on failure.
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  void write(const void* data, std::size_t bytes);
  void write(std::span<const std::byte> bytes) { write(bytes.data(), bytes.size()); }
  void write(const std::string& text) { write(text.data(), text.size()); }
  /// Flushes, fsyncs and renames the temporary file to the target.
  void commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporary() const { return temp_; }

private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

/// Writes a whole buffer atomically.
void write_file_atomic(const std::filesystem::path& target, const void* data, std::size_t bytes);
inline void write_file_atomic(const std::filesystem::path& target, const std::string& text) {
  write_file_atomic(target, text.data(), text.size());
}

/// Reads a whole file; throws matlas::Error naming the file if it is missing or unreadable.
std::string read_file(const std::filesystem::path& path);

}  // namespace matlas
