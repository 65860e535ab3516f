// AtomicFile: appends, holes filled later, direct-I/O streaming of large appends; the target
// appears only on commit and the temporary file never outlives a failed write.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sys/stat.h>
#include <unistd.h>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/direct_appender.h"
#include "core/error.h"
#include "core/file_io.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

std::string random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

TEST(AtomicFile, AppendsSkipsAndPositionalWritesLandWhereTheyBelong) {
  test::TempDir dir;
  const auto target = dir / "out.bin";
  {
    AtomicFile f(target);
    f.write(std::string("head"));
    f.skip(6);
    f.write(std::string("tail"));
    EXPECT_EQ(f.position(), 14u);
    f.write_at(4, "middle", 6);
    EXPECT_FALSE(std::filesystem::exists(target));
    f.commit();
  }
  EXPECT_EQ(read_file(target), "headmiddletail");
}

TEST(AtomicFile, UncommittedOutputLeavesNothingBehind) {
  test::TempDir dir;
  std::filesystem::path temporary;
  {
    AtomicFile f(dir / "out.bin");
    f.stream_appends_to_disk();
    f.write(random_bytes(DirectAppender::kBufferBytes + 5000, 1));
    temporary = f.temporary();
    EXPECT_TRUE(std::filesystem::exists(temporary));
  }
  EXPECT_FALSE(std::filesystem::exists(temporary));
  EXPECT_FALSE(std::filesystem::exists(dir / "out.bin"));
}

TEST(AtomicFile, StreamedAppendsAfterAnUnalignedHeadRoundTrip) {
  // A hole and an unaligned start (filled by ordinary writes), then several staging buffers
  // and a partial one in pieces of odd sizes: the file must read back byte for byte.
  test::TempDir dir;
  const auto target = dir / "big.bin";
  const std::string header = random_bytes(1000, 2);
  const std::string body = random_bytes(2 * DirectAppender::kBufferBytes + 123457, 3);
  {
    AtomicFile f(target);
    f.skip(header.size());
    f.stream_appends_to_disk();
    for (std::size_t at = 0; at < body.size();) {
      const std::size_t piece = std::min<std::size_t>(body.size() - at, 777777 + at % 1000);
      f.write(body.data() + at, piece);
      at += piece;
    }
    f.write_at(0, header.data(), header.size());
    f.commit();
  }
  const std::string back = read_file(target);
  ASSERT_EQ(back.size(), header.size() + body.size());
  EXPECT_TRUE(back.compare(0, header.size(), header) == 0);
  EXPECT_TRUE(back.compare(header.size(), body.size(), body) == 0);
}

/// A direct appender on a new empty file at `path`; null where the file system has no direct I/O.
std::unique_ptr<DirectAppender> open_empty(const std::filesystem::path& path) {
  write_file_atomic(path, std::string());
  return DirectAppender::open(path, 0);
}

TEST(DirectAppender, WritesWholeBuffersAndHandsBackTheTail) {
  test::TempDir dir;
  const auto path = dir / "direct.bin";
  auto direct = open_empty(path);
  if (!direct) GTEST_SKIP() << "the file system of " << dir.path() << " has no direct I/O";
  const std::string data = random_bytes(DirectAppender::kBufferBytes + 4100, 4);
  direct->append(data.data(), data.size());
  const auto tail = direct->finish();
  EXPECT_EQ(tail.size(), 4100u);
  EXPECT_EQ(direct->tail_offset(), DirectAppender::kBufferBytes);
  const std::string back = read_file(path);
  ASSERT_EQ(back.size(), DirectAppender::kBufferBytes);
  EXPECT_TRUE(back.compare(0, back.size(), data, 0, back.size()) == 0);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(tail.data()), tail.size()), data.substr(back.size()));
}

// More full buffers than the appender keeps (kMaxBuffers): the writer frees them in order and
// they are filled again; every buffer lands at its offset, none is written twice or skipped.
TEST(DirectAppender, RecycledBuffersKeepTheirOrder) {
  test::TempDir dir;
  const auto path = dir / "direct.bin";
  auto direct = open_empty(path);
  if (!direct) GTEST_SKIP() << "the file system of " << dir.path() << " has no direct I/O";
  const std::size_t buffers = DirectAppender::kMaxBuffers + 3;
  const std::string data = random_bytes(buffers * DirectAppender::kBufferBytes + 999, 5);
  direct->append(data.data(), 5 * DirectAppender::kBufferBytes / 2);  // in two appends, the first
  direct->append(data.data() + 5 * DirectAppender::kBufferBytes / 2,  // ending mid-buffer
                 data.size() - 5 * DirectAppender::kBufferBytes / 2);
  const auto tail = direct->finish();
  EXPECT_EQ(tail.size(), 999u);
  EXPECT_EQ(direct->tail_offset(), buffers * DirectAppender::kBufferBytes);
  const std::string back = read_file(path);
  ASSERT_EQ(back.size(), buffers * DirectAppender::kBufferBytes);
  EXPECT_TRUE(back == data.substr(0, back.size()));
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(tail.data()), tail.size()), data.substr(back.size()));
}

}  // namespace
}  // namespace matlas

// ---- Hardening (issue 14): stale temporaries, empty names, folders, non-regular inputs
namespace matlas {
namespace {

TEST(AtomicFileHardening, StaleTemporariesOfDeadProcessesAreRemoved) {
  test::TempDir dir;
  const auto target = dir.path() / "out.bin";
  std::ofstream(dir.path() / "out.bin.tmp-4194301") << "stale";            // no such process
  std::ofstream(dir.path() / ("out.bin.tmp-" + std::to_string(::getppid()))) << "alive";  // a live process
  std::ofstream(dir.path() / "other.bin.tmp-4194301") << "another target";
  std::ofstream(dir.path() / "out.bin.tmp-notapid") << "not ours";
  write_file_atomic(target, std::string("x"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out.bin.tmp-4194301"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / ("out.bin.tmp-" + std::to_string(::getppid()))));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "other.bin.tmp-4194301"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "out.bin.tmp-notapid"));
}

TEST(AtomicFileHardening, EmptyNamesAndFoldersAreRefused) {
  test::TempDir dir;
  try {
    AtomicFile f("");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("output file name is empty"), std::string::npos);
  }
  try {
    AtomicFile f(dir.path());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos);
  }
}

TEST(AtomicFileHardening, NonRegularInputsAreRefusedWithoutBlocking) {
  test::TempDir dir;
  const auto fifo = dir.path() / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  try {
    (void)read_file(fifo);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a named pipe (FIFO)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(open_regular_file("/dev/null", "a test file"), Error);
  EXPECT_THROW(open_regular_file(dir.path(), "a test file"), Error);
}

}  // namespace
}  // namespace matlas
