#pragma once
// Whole-buffer positional reads and writes on a file descriptor: pread/pwrite repeated over short
// transfers and EINTR, errors as matlas::Error naming the file.
#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace matlas {

/// Reads exactly `bytes` at `offset`; a file that ends first is reported as truncated.
void read_exact_at(int fd, const std::filesystem::path& path, void* out, std::size_t bytes, std::uint64_t offset);

/// Writes all `bytes` at `offset`.
void write_all_at(int fd, const std::filesystem::path& path, const void* data, std::size_t bytes,
                  std::uint64_t offset);

}  // namespace matlas
