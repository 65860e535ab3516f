// BlockPrefetch: every block of every file arrives with the file's bytes, more blocks than
// buffers (the buffers are reused in order), a last block shorter than the others, a share of the
// blocks, a prefetch dropped before the pass ends (its threads stop), and a read error at the
// block that meets it.
#include "manifold/block_prefetch.h"

#include <cstdio>
#include <cstring>
#include <gtest/gtest.h>
#include <sys/resource.h>

#include "support/error_of.h"
#include "support/temp_dir.h"
#include "synthetic_database.h"

namespace matlas {
namespace {

constexpr MerlDims kPrefetchDims{6, 6, 12};  // 432 bins, 1296 values

std::vector<std::filesystem::path> small_database(const std::filesystem::path& dir, int n) {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> paths;
  for (int m = 0; m < n; ++m) {
    char name[32];
    std::snprintf(name, sizeof name, "p%d.binary", m);  // not string concatenation: GCC 12's -Wrestrict
    paths.push_back(dir / name);
    write_merl(paths.back(), test::smooth_table(0.2 * m, 0.5, kPrefetchDims), /*allow_nonstandard_dims=*/true);
  }
  return paths;
}

/// Compares block b of file i with the file's values.
void expect_block(BlockPrefetch& prefetch, const MaterialSet& set, std::size_t step, std::size_t b, std::size_t i) {
  const std::size_t first = b * step, count = std::min(step, set.value_count() - first);
  std::vector<double> want(count), got(count);
  set.file(i).read_values(first, count, want.data());
  std::memcpy(got.data(), prefetch.bytes(b, i), count * sizeof(double));
  EXPECT_EQ(got, want) << "block " << b << ", file " << i;
}

TEST(BlockPrefetch, DeliversEveryBlockOfEveryFile) {
  test::TempDir dir;
  const MaterialSet set = MaterialSet::open(small_database(dir / "db", 5));
  const std::size_t step = 100, blocks = (set.value_count() + step - 1) / step;  // 13, the last 96 values
  {
    BlockPrefetch prefetch(set, step, 0, blocks);
    EXPECT_GE(prefetch.slots(), 2u);
    EXPECT_LT(prefetch.slots(), blocks);  // the buffers are reused
    for (std::size_t b = 0; b < blocks; ++b) {
      for (std::size_t i = set.size(); i-- > 0;) expect_block(prefetch, set, step, b, i);  // any order within a block
      prefetch.done(b);
    }
  }
  {
    BlockPrefetch share(set, step, 4, 9);
    for (std::size_t b = 4; b < 9; ++b) {
      for (std::size_t i = 0; i < set.size(); ++i) expect_block(share, set, step, b, i);
      share.done(b);
    }
  }
  {
    BlockPrefetch dropped(set, 64, 0, set.value_count() / 64);
    expect_block(dropped, set, 64, 0, 2);
  }  // destroyed with reads outstanding: returns
}

// More files than a common soft limit on open descriptors allows (1024 on many systems; 128 here):
// the set and the prefetch's second descriptors raise it towards the hard limit.
TEST(BlockPrefetch, OpensMoreFilesThanTheSoftDescriptorLimit) {
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &saved), 0);
  if (saved.rlim_max != RLIM_INFINITY && saved.rlim_max < 1000) GTEST_SKIP() << "hard limit " << saved.rlim_max;
  test::TempDir dir;
  const auto paths = small_database(dir / "db", 200);
  rlimit low = saved;
  low.rlim_cur = 128;
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &low), 0);
  {
    const MaterialSet set = MaterialSet::open(paths);
    BlockPrefetch prefetch(set, 500, 0, 3);
    for (std::size_t i = 0; i < set.size(); i += 37) expect_block(prefetch, set, 500, 0, i);
  }
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &saved), 0);
}

TEST(BlockPrefetch, ReportsAReadErrorAtItsBlock) {
  test::TempDir dir;
  const auto paths = small_database(dir / "db", 3);
  const MaterialSet set = MaterialSet::open(paths);
  const std::size_t step = 128, blocks = (set.value_count() + step - 1) / step;
  std::filesystem::resize_file(paths[1], MerlFile::value_offset(5 * step + 10));  // block 5 of p1 is cut short
  BlockPrefetch prefetch(set, step, 0, blocks);
  for (std::size_t b = 0; b < 5; ++b) {
    for (std::size_t i = 0; i < set.size(); ++i) EXPECT_NE(prefetch.bytes(b, i), nullptr);
    prefetch.done(b);
  }
  EXPECT_NE(prefetch.bytes(5, 0), nullptr);
  const std::string e = test::error_of([&] { prefetch.bytes(5, 1); });
  EXPECT_NE(e.find("p1.binary: truncated"), std::string::npos) << e;
}

}  // namespace
}  // namespace matlas
