#pragma once
// Whole-buffer positional reads and writes on a file descriptor: pread/pwrite repeated over short
// transfers and EINTR, errors as matlas::Error naming the file.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace matlas {

/// Refuses to write `output` when it is one of `inputs` (writing it would replace an input): the
/// same file by device and inode (through any symlink or hard link), or the same canonical path.
/// Inputs that do not exist (names such as "studio" for an installed map) never match. Throws
/// matlas::Error naming the output and the input. Every command that writes a file calls it with
/// all the files it reads.
void refuse_output_among_inputs(const std::filesystem::path& output, const std::vector<std::filesystem::path>& inputs);

/// Opens an existing file read-only, refusing anything that is not a regular file (a FIFO would
/// block the reader forever, a device never ends): the check is made on the opened descriptor
/// (opened non-blocking, so a FIFO without a writer does not hang). Throws matlas::Error naming
/// the file: missing, a directory, a FIFO, a socket, a device, unreadable. `expected` completes
/// "PATH: is a FIFO, not EXPECTED" (e.g. "a MERL .binary file").
int open_regular_file(const std::filesystem::path& path, const std::string& expected);

/// Makes room for `count` open files in this process: raises the soft limit on open descriptors
/// (often 1024) towards the hard one when it is lower. A database of a thousand materials keeps a
/// descriptor per file, and a pass that reads it around the page cache a second one. Returns
/// whether the limit now allows `count`.
bool allow_open_files(std::size_t count);

/// What kind of file st_mode is, in words ("a directory", "a named pipe (FIFO)", ...).
std::string file_kind(unsigned mode);

/// Reads exactly `bytes` at `offset`; a file that ends first is reported as truncated.
void read_exact_at(int fd, const std::filesystem::path& path, void* out, std::size_t bytes, std::uint64_t offset);

/// Writes all `bytes` at `offset`.
void write_all_at(int fd, const std::filesystem::path& path, const void* data, std::size_t bytes,
                  std::uint64_t offset);

}  // namespace matlas
