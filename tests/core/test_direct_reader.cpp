// DirectReader against plain reads of the same file: ranges at any offset and size, at the start
// and the end of the file, with the file in the page cache and after it has left it (direct reads
// where the file system allows them), an unlinked file, and the errors of a range past the end.
#include "core/direct_reader.h"

#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <memory>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

#include "core/file_io.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

std::vector<std::byte> random_content(std::size_t size) {
  std::mt19937_64 rng(11);
  std::vector<std::byte> bytes(size);
  for (std::byte& b : bytes) b = static_cast<std::byte>(rng() & 0xff);
  return bytes;
}

struct AlignedFree {
  void operator()(std::byte* p) const { std::free(p); }
};

/// Reads [offset, offset + size) through `reader` into a fresh aligned buffer and compares.
void expect_range(const DirectReader& reader, const std::vector<std::byte>& content, std::uint64_t offset,
                  std::size_t size) {
  const std::size_t span = DirectReader::span(offset, size);
  ASSERT_EQ(span % DirectReader::kAlignment, 0u);
  ASSERT_GE(span, size);
  std::unique_ptr<std::byte, AlignedFree> buffer(
      static_cast<std::byte*>(std::aligned_alloc(DirectReader::kAlignment, span)));
  const std::byte* at = reader.read(offset, size, buffer.get());
  ASSERT_GE(at, buffer.get());
  ASSERT_LE(at + size, buffer.get() + span);
  EXPECT_EQ(std::memcmp(at, content.data() + offset, size), 0) << "offset " << offset << ", " << size << " bytes";
}

void expect_ranges(const DirectReader& reader, const std::vector<std::byte>& content) {
  const std::size_t size = content.size();
  for (const auto& [offset, bytes] : std::vector<std::pair<std::uint64_t, std::size_t>>{
           {0, 1}, {0, 4096}, {12, 8 * 700}, {4092, 8}, {4096, 3 * 4096}, {size / 3 + 1, size / 4},
           {size - 5, 5}, {size - 4096 - 7, 4096 + 7}, {0, size}, {size / 2 + 3, size / 2 - 3}})
    expect_range(reader, content, offset, bytes);
}

TEST(DirectReader, ReadsTheSameBytesCachedOrNot) {
  test::TempDir dir;
  const auto path = dir / "data.bin";
  const std::vector<std::byte> content = random_content(3 * 65536 + 1237);  // ends inside a block
  {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0);
    write_all_at(fd, path, content.data(), content.size(), 0);
    ASSERT_EQ(::fsync(fd), 0);
    ::close(fd);
  }
  const int fd = open_regular_file(path, "a test file");
  DirectReader reader(fd, path);
  if (!reader.direct()) std::printf("note: %s refuses direct reads: every read went through the page cache\n",
                                    dir.path().c_str());
  expect_ranges(reader, content);  // written just now: in the page cache
  ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);  // clean pages leave it: read from the device
  expect_ranges(reader, content);
  DirectReader moved(std::move(reader));
  expect_range(moved, content, 777, 20000);

  // Past the end: the file is reported as truncated, by name.
  std::unique_ptr<std::byte, AlignedFree> buffer(static_cast<std::byte*>(
      std::aligned_alloc(DirectReader::kAlignment, DirectReader::span(content.size() - 10, 100))));
  const std::string e = test::error_of([&] { moved.read(content.size() - 10, 100, buffer.get()); });
  EXPECT_NE(e.find("data.bin: truncated"), std::string::npos) << e;
  ::close(fd);
}

TEST(DirectReader, ReadsAnUnlinkedFile) {
  test::TempDir dir;
  const auto path = dir / "gone.bin";
  const std::vector<std::byte> content = random_content(2 * 65536 + 4099);
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  write_all_at(fd, path, content.data(), content.size(), 0);
  ASSERT_EQ(::fsync(fd), 0);
  std::filesystem::remove(path);
  ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
  const DirectReader reader(fd, path);
  expect_ranges(reader, content);
  ::close(fd);
}

}  // namespace
}  // namespace matlas
