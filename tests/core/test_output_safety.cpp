// Outputs that must not destroy anything (issue 28): the temporary file of an AtomicFile is never
// opened through a planted symlink, an output that is one of the inputs is refused (by any
// spelling, symlink or hard link), and a CommitCheck that fails leaves no output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/direct_appender.h"
#include "core/error.h"
#include "core/file_io.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

fs::path own_temporary(const fs::path& target) { return target.string() + ".tmp-" + std::to_string(::getpid()); }

TEST(TemporaryFiles, APlantedSymlinkAtTheTemporaryNameIsNotFollowed) {
  test::TempDir dir;
  const fs::path victim = dir / "victim.txt", target = dir / "out.bin";
  std::ofstream(victim) << "precious";
  fs::create_symlink(victim, own_temporary(target));  // the predictable name, planted
  write_file_atomic(target, std::string("output"));
  EXPECT_EQ(read_file(victim), "precious");
  EXPECT_EQ(read_file(target), "output");
  EXPECT_FALSE(fs::is_symlink(target));
  EXPECT_FALSE(fs::exists(fs::symlink_status(own_temporary(target))));
}

TEST(TemporaryFiles, APlantedSymlinkIsNotFollowedByStreamedAppendsEither) {
  test::TempDir dir;
  const fs::path victim = dir / "victim.txt", target = dir / "out.bin";
  std::ofstream(victim) << "precious";
  fs::create_symlink(victim, own_temporary(target));
  const std::string data(DirectAppender::kBufferBytes + 12345, 'x');
  {
    AtomicFile f(target);
    f.stream_appends_to_disk();
    f.write(data);
    f.commit();
  }
  EXPECT_EQ(read_file(victim), "precious");
  EXPECT_EQ(fs::file_size(target), data.size());
}

TEST(TemporaryFiles, AStaleTemporaryOfOurOwnPidIsReplacedNotAppendedTo) {
  test::TempDir dir;
  const fs::path target = dir / "out.bin";
  std::ofstream(own_temporary(target)) << "left by a killed process that had this pid, and long";
  write_file_atomic(target, std::string("new"));
  EXPECT_EQ(read_file(target), "new");
}

TEST(TemporaryFiles, TwoOutputsOfOneTargetAtOnceDoNotShareATemporary) {
  test::TempDir dir;
  const fs::path target = dir / "out.bin";
  AtomicFile a(target), b(target);
  EXPECT_NE(a.temporary(), b.temporary());
  a.write(std::string("first"));
  b.write(std::string("second"));
  a.commit();
  EXPECT_EQ(read_file(target), "first");
  b.commit();
  EXPECT_EQ(read_file(target), "second");
}

TEST(TemporaryFiles, StaleSecondTemporariesOfDeadProcessesAreRemoved) {
  test::TempDir dir;
  std::ofstream(dir / "out.bin.tmp-4194301-2") << "stale";
  std::ofstream(dir / "out.bin.tmp-4194301-x") << "not ours";
  write_file_atomic(dir / "out.bin", std::string("x"));
  EXPECT_FALSE(fs::exists(dir / "out.bin.tmp-4194301-2"));
  EXPECT_TRUE(fs::exists(dir / "out.bin.tmp-4194301-x"));
}

TEST(TemporaryFiles, DirectAppendsRefuseASymlinkOrAnotherFile) {
  test::TempDir dir;
  std::ofstream(dir / "a") << "";
  std::ofstream(dir / "b") << "";
  fs::create_symlink(dir / "a", dir / "link");
  EXPECT_EQ(DirectAppender::open(dir / "link", 0), nullptr);
  const int fd = open_regular_file(dir / "a", "a test file");
  EXPECT_EQ(DirectAppender::open(dir / "b", 0, fd), nullptr);  // not the caller's file
  ::close(fd);
}

TEST(CommitChecks, AFailingCheckLeavesNoOutputAndNoTemporary) {
  test::TempDir dir;
  const fs::path target = dir / "out.bin";
  std::ofstream(target) << "before";
  fs::path temporary;
  {
    const CommitCheck refuse([] { throw Error("input.matlas: changed while it was read"); });
    AtomicFile f(target);
    temporary = f.temporary();
    f.write(std::string("wrong answer"));
    EXPECT_EQ(error_of([&] { f.commit(); }), "input.matlas: changed while it was read");
  }
  EXPECT_EQ(read_file(target), "before");
  EXPECT_FALSE(fs::exists(temporary));
  write_file_atomic(target, std::string("after"));  // the check is gone with its object
  EXPECT_EQ(read_file(target), "after");
}

TEST(OutputAmongInputs, TheSameFileIsRefusedThroughAnySpellingOrLink) {
  test::TempDir dir;
  fs::create_directories(dir / "sub");
  const fs::path input = dir / "model.matlas", other = dir / "other.matlas";
  std::ofstream(input) << "model";
  std::ofstream(other) << "other";
  fs::create_symlink(input, dir / "symlink.matlas");
  fs::create_hard_link(input, dir / "hardlink.matlas");
  for (const fs::path& output : {input, dir / "sub" / ".." / "model.matlas", dir / "symlink.matlas",
                                 dir / "hardlink.matlas"}) {
    const std::string e = error_of([&] { refuse_output_among_inputs(output, {other, input}); });
    EXPECT_EQ(e, output.string() + ": the output is one of the inputs (" + input.string() +
                     "): refusing to overwrite it; choose another output name");
  }
  // An input given through a link is the same file too.
  EXPECT_NE(error_of([&] { refuse_output_among_inputs(input, {dir / "symlink.matlas"}); }), "");
  // Other files, new files, inputs that are not files (an installed map's name): accepted.
  EXPECT_EQ(error_of([&] { refuse_output_among_inputs(dir / "new.binary", {input, other}); }), "");
  EXPECT_EQ(error_of([&] { refuse_output_among_inputs(other, {input, "studio", ""}); }), "");
  EXPECT_EQ(read_file(input), "model");
}

}  // namespace
}  // namespace matlas
