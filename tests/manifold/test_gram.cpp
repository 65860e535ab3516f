// The build's pass (accumulate_gram) against a direct computation on whole tables: validity
// mask, mean, both Gram matrices and the albedo curves for every layout transform, with dropped columns in runs and
// alone, blocks that do not divide the data, and sweep ranges cut short.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <gtest/gtest.h>

#include "brdf/albedo_operator.h"
#include "brdf/merl_grid.h"
#include "manifold/gram.h"
#include "manifold/gram_update.h"
#include "manifold/kept_runs.h"
#include "manifold/layout_transform.h"
#include "support/error_of.h"
#include "support/temp_dir.h"
#include "synthetic_database.h"

namespace matlas {
namespace {

using test::TempDir;

constexpr MerlDims kDims{10, 8, 24};  // 1920 bins, 5760 values: several blocks and sweep ranges

/// Writes n materials, some with unmeasured values (stored -1): a long run, isolated bins, and a
/// run that crosses a channel boundary.
std::vector<std::filesystem::path> database_with_gaps(const std::filesystem::path& dir, int n) {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> paths;
  for (int m = 0; m < n; ++m) {
    BrdfTable t = test::smooth_table(0.1 * m, 0.7 - 0.05 * m, kDims);
    auto stored = t.stored();
    if (m == 0)
      for (std::size_t v = 100; v < 700; ++v) stored[v] = -1.0;
    if (m == 1)
      for (std::size_t v = 3; v < stored.size(); v += 37) stored[v] = -1.0;
    if (m == 2)
      for (std::size_t v = 1900; v < 1950; ++v) stored[v] = -1.0;  // red -> green
    char name[32];
    std::snprintf(name, sizeof name, "m%d.binary", m);
    paths.push_back(dir / name);
    write_merl(paths.back(), t, /*allow_nonstandard_dims=*/true);
  }
  return paths;
}

struct Direct {
  std::vector<bool> kept;
  Eigen::VectorXd mean;
  Eigen::MatrixXd gram, layout_gram, albedo;
};

/// The same quantities from whole tables, by the definitions.
Direct direct(const std::vector<std::filesystem::path>& paths, const LayoutTransform& layout) {
  const auto n = static_cast<Eigen::Index>(paths.size());
  std::vector<BrdfTable> tables;
  for (const auto& p : paths) tables.push_back(read_merl(p));
  const std::size_t bins = kDims.bins(), values = 3 * bins;
  const std::vector<double> cosine = bin_cosine_factors(kDims);
  Direct d;
  d.kept.assign(values, true);
  std::vector<std::size_t> columns;
  for (std::size_t v = 0; v < values; ++v) {
    for (const BrdfTable& t : tables) d.kept[v] = d.kept[v] && t.stored()[v] >= 0.0;
    if (d.kept[v]) columns.push_back(v);
  }
  const auto k = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd z(n, k), g(n, k);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index c = 0; c < k; ++c) {
      const std::size_t v = columns[static_cast<std::size_t>(c)];
      const double x = tables[static_cast<std::size_t>(i)].value(static_cast<int>(v / bins), v % bins);
      z(i, c) = x;
      double y = layout.map == LayoutTransform::Map::cube_root ? std::cbrt(x)
                 : layout.map == LayoutTransform::Map::log     ? std::log1p(100.0 * x)
                                                               : x;
      if (layout.cosine_weighted) y *= cosine[v % bins];
      g(i, c) = y;
    }
  d.mean = z.colwise().mean().transpose();
  // Albedo curves of the kept data: slot t * 3 + channel sums op(bin, t) * value.
  const auto op = albedo_operator(kDims, 90);
  d.albedo = Eigen::MatrixXd::Zero(n, 90 * 3);
  for (Eigen::Index c = 0; c < k; ++c) {
    const std::size_t v = columns[static_cast<std::size_t>(c)];
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(op, static_cast<Eigen::Index>(v % bins)); it; ++it)
      d.albedo.col(it.col() * 3 + static_cast<Eigen::Index>(v / bins)) += it.value() * z.col(c);
  }
  const Eigen::MatrixXd zc = z.rowwise() - z.colwise().mean();
  const Eigen::MatrixXd gc = g.rowwise() - g.colwise().mean();
  d.gram = zc * zc.transpose();
  d.layout_gram = gc * gc.transpose();
  return d;
}

TEST(GramPass, MatchesTheDefinitionsForEveryLayout) {
  TempDir dir;
  const auto paths = database_with_gaps(dir / "db", 6);
  const MaterialSet set = MaterialSet::open(paths);
  for (const char* name : {"linear", "cosine-linear", "cbrt", "cosine-cbrt", "log", "cosine-log"}) {
    const LayoutTransform layout = LayoutTransform::parse(name);
    const Direct want = direct(paths, layout);
    for (const std::size_t block : {std::size_t{700}, std::size_t{4096}}) {
      SCOPED_TRACE(std::string(name) + ", blocks of " + std::to_string(block));
      const GramResult got = accumulate_gram(set, layout, block, null_progress());
      ASSERT_EQ(got.kept, want.kept);
      ASSERT_EQ(got.kept_columns, static_cast<std::size_t>(want.mean.size()));
      EXPECT_LT((got.mean - want.mean).norm(), 1e-14 * want.mean.norm());
      EXPECT_LT((got.gram - want.gram).norm(), 1e-12 * want.gram.norm());
      // The layout's data and slice products are single precision (manifold/gram_update.h):
      // about 1e-7 relative (up to 4e-7 here; 1.2e-7 on the 83 realistic materials).
      EXPECT_LT((got.layout_gram - want.layout_gram).norm(), 1e-6 * want.layout_gram.norm());
      EXPECT_LT((got.albedo - want.albedo).norm(), 1e-12 * want.albedo.norm());
    }
  }
}

// A distributed build's shares (one per rank): concatenated, their masks and means are the whole
// pass's exactly, and their Gram matrices and albedo curves add up to the whole's to rounding.
TEST(GramPass, SharesAddUpToTheWholePass) {
  TempDir dir;
  const auto paths = database_with_gaps(dir / "db", 6);
  const MaterialSet set = MaterialSet::open(paths);
  const LayoutTransform layout = LayoutTransform::parse("cosine-cbrt");
  const std::size_t block = 700;
  const GramResult whole = accumulate_gram(set, layout, block, null_progress());
  const std::size_t blocks = (set.value_count() + block - 1) / block;
  for (const int parts : {2, 3, static_cast<int>(blocks) + 2}) {  // the last: ranks without a block
    SCOPED_TRACE(std::to_string(parts) + " shares");
    GramResult sum, exact;
    std::vector<bool> kept;
    std::vector<double> mean;
    std::size_t next = 0;
    for (int part = 0; part < parts; ++part) {
      GramResult g = accumulate_gram(set, layout, block, null_progress(), nullptr, {part, parts});
      EXPECT_EQ(g.first_value, next);
      next = g.end_value;
      for (std::size_t v = g.first_value; v < g.end_value; ++v) kept.push_back(g.kept[v]);
      mean.insert(mean.end(), g.mean.data(), g.mean.data() + g.mean.size());
      if (part == 0) {
        sum = std::move(g);
        exact = sum;
      } else {
        sum.gram += g.gram;
        sum.layout_gram += g.layout_gram;
        sum.albedo += g.albedo;
        // As the ranks add them (Communicator::sum_compensated): with the parts' rounding rests.
        for (Eigen::Index k = 0; k < g.gram.size(); ++k) {
          add_compensated(exact.gram.data()[k], exact.gram_low.data()[k], g.gram.data()[k]);
          exact.gram_low.data()[k] += g.gram_low.data()[k];
          add_compensated(exact.layout_gram.data()[k], exact.layout_gram_low.data()[k], g.layout_gram.data()[k]);
          exact.layout_gram_low.data()[k] += g.layout_gram_low.data()[k];
        }
      }
    }
    round_compensated(exact.gram, exact.gram_low);
    round_compensated(exact.layout_gram, exact.layout_gram_low);
    // Compensated sums: the whole pass's bits, whatever the split.
    EXPECT_EQ(exact.gram, whole.gram);
    EXPECT_EQ(exact.layout_gram, whole.layout_gram);
    EXPECT_EQ(next, set.value_count());
    EXPECT_EQ(kept, whole.kept);
    ASSERT_EQ(mean.size(), static_cast<std::size_t>(whole.mean.size()));
    EXPECT_EQ(Eigen::Map<const Eigen::VectorXd>(mean.data(), whole.mean.size()), whole.mean);  // bitwise
    EXPECT_LT((sum.gram - whole.gram).norm(), 1e-13 * whole.gram.norm());
    EXPECT_LT((sum.layout_gram - whole.layout_gram).norm(), 1e-6 * whole.layout_gram.norm());
    EXPECT_LT((sum.albedo - whole.albedo).norm(), 1e-13 * whole.albedo.norm());
  }
}

// The automatic block width: narrow for a few hundred files, wide from 512 on, never a block past
// 256 MB nor narrower than 4096 columns, a multiple of the Gram's slices; 0 asks for it.
TEST(GramPass, BlockWidthFollowsTheNumberOfMaterials) {
  EXPECT_EQ(default_block_columns(1), 4096u);
  EXPECT_EQ(default_block_columns(511), 4096u);
  EXPECT_EQ(default_block_columns(512), 16384u);
  EXPECT_EQ(default_block_columns(1000), 16384u);
  EXPECT_EQ(default_block_columns(2048), 16384u);   // 256 MB exactly
  EXPECT_EQ(default_block_columns(3000), 10240u);   // 11184 columns fit, rounded down to slices
  EXPECT_EQ(default_block_columns(10000), 4096u);   // 3355 fit: the narrowest width instead
  for (const std::size_t n : {600u, 1500u, 2500u, 4000u, 6000u, 8191u}) {
    const std::size_t w = default_block_columns(n);
    EXPECT_EQ(w % GramAccumulator::kSlice, 0u) << n;
    EXPECT_TRUE(w == 4096 || n * w * sizeof(double) <= (std::size_t{256} << 20)) << n;
  }
  EXPECT_EQ(resolved_block_columns(0, 1000), 16384u);
  EXPECT_EQ(resolved_block_columns(700, 1000), 700u);

  TempDir dir;
  const auto paths = database_with_gaps(dir / "db", 6);
  const MaterialSet set = MaterialSet::open(paths);
  const LayoutTransform layout = LayoutTransform::parse("cosine-cbrt");
  const GramResult automatic = accumulate_gram(set, layout, 0, null_progress());
  const GramResult narrow = accumulate_gram(set, layout, 4096, null_progress());
  EXPECT_EQ(automatic.gram, narrow.gram);  // 6 materials: the 4096-column blocks, bit for bit
  EXPECT_EQ(automatic.layout_gram, narrow.layout_gram);
}

// Reads ahead around the page cache (BlockPrefetch, the default for databases larger than memory)
// give the page cache's results bit for bit: blocks that do not divide the data, shares, the
// hashes of the files; and the same errors: a NaN read, a file cut short after it was opened.
TEST(GramPass, PrefetchedReadsGiveThePageCacheResults) {
  TempDir dir;
  auto paths = database_with_gaps(dir / "db", 7);
  const MaterialSet set = MaterialSet::open(paths);
  const LayoutTransform layout = LayoutTransform::parse("cosine-cbrt");
  for (const std::size_t block : {std::size_t{700}, std::size_t{4096}}) {
    for (const int parts : {1, 2}) {
      SCOPED_TRACE("blocks of " + std::to_string(block) + ", " + std::to_string(parts) + " shares");
      for (int part = 0; part < parts; ++part) {
        const GramResult cached =
            accumulate_gram(set, layout, block, null_progress(), nullptr, {part, parts}, PassReads::page_cache);
        const GramResult ahead =
            accumulate_gram(set, layout, block, null_progress(), nullptr, {part, parts}, PassReads::prefetch);
        EXPECT_EQ(ahead.kept, cached.kept);
        EXPECT_EQ(ahead.mean, cached.mean);
        EXPECT_EQ(ahead.gram, cached.gram);
        EXPECT_EQ(ahead.gram_low, cached.gram_low);
        EXPECT_EQ(ahead.layout_gram, cached.layout_gram);
        EXPECT_EQ(ahead.albedo, cached.albedo);
        EXPECT_EQ(ahead.hashes, cached.hashes);
      }
    }
  }

  // A NaN in the fourth file, far into the table: the error names the file and the bin.
  {
    std::fstream bad(paths[3], std::ios::in | std::ios::out | std::ios::binary);  // write_merl refuses a NaN
    const double nan = std::nan("");
    bad.seekp(static_cast<std::streamoff>(MerlFile::value_offset(5000)));
    bad.write(reinterpret_cast<const char*>(&nan), sizeof nan);
    bad.close();
    const MaterialSet with_nan = MaterialSet::open(paths);
    const std::string e = test::error_of(
        [&] { accumulate_gram(with_nan, layout, 700, null_progress(), nullptr, {}, PassReads::prefetch); });
    EXPECT_NE(e.find("m3.binary: NaN value in the blue channel at bin 1160"), std::string::npos) << e;
  }
  // The sixth file cut short after the set was opened (changed during a build).
  paths = database_with_gaps(dir / "db2", 7);
  const MaterialSet cut = MaterialSet::open(paths);
  std::filesystem::resize_file(paths[5], std::filesystem::file_size(paths[5]) - 3000);
  const std::string e =
      test::error_of([&] { accumulate_gram(cut, layout, 700, null_progress(), nullptr, {}, PassReads::prefetch); });
  EXPECT_NE(e.find("m5.binary: truncated"), std::string::npos) << e;
}

TEST(KeptRuns, SplitAtRangeBoundariesAndCompact) {
  const std::vector<std::uint8_t> kept = {1, 1, 0, 1, 1, 1, 1, 0, 0, 1};
  const KeptRuns r = kept_runs(kept.data(), kept.size(), 4);
  // Ranges [0, 4), [4, 8), [8, 10): runs {0-1}, {3}; {4-6}; {9}.
  ASSERT_EQ(r.runs.size(), 4u);
  EXPECT_EQ(r.kept, 7u);
  ASSERT_EQ(r.range_begin, (std::vector<std::size_t>{0, 2, 3, 4}));
  const std::size_t want[4][3] = {{0, 2, 0}, {3, 1, 2}, {4, 3, 3}, {9, 1, 6}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(r.runs[i].first, want[i][0]);
    EXPECT_EQ(r.runs[i].count, want[i][1]);
    EXPECT_EQ(r.runs[i].out, want[i][2]);
  }
  EXPECT_TRUE(kept_runs(kept.data(), 0, 4).runs.empty());
}

// The sweep's layout copy of a range (manifold/layout_transform.h), against its definition in
// double: for every map, with and without cosine weights, over runs with gaps; the centred copy
// exactly, the layout copy to single precision, both compacted, and nothing written past them.
TEST(LayoutCopy, CentresBothCopiesOfTheKeptColumnsForEveryMap) {
  const Eigen::Index rows = 7, columns = 24;
  const std::size_t ld = 32;
  BlockMatrix values(rows, columns);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  for (Eigen::Index k = 0; k < values.size(); ++k) values.data()[k] = u(rng);
  std::vector<std::uint8_t> kept(columns, 1);
  for (const int dropped : {0, 5, 6, 13, 23}) kept[static_cast<std::size_t>(dropped)] = 0;
  const KeptRuns runs = kept_runs(kept.data(), kept.size(), 64);
  ASSERT_EQ(runs.kept, 19u);
  std::vector<double> mean(columns);
  std::vector<float> cosine(columns);
  for (Eigen::Index j = 0; j < columns; ++j) {
    mean[static_cast<std::size_t>(j)] = values.col(j).mean();
    cosine[static_cast<std::size_t>(j)] = 0.2f + 0.03f * static_cast<float>(j);
  }
  for (const char* name : {"linear", "cosine-linear", "cbrt", "cosine-cbrt", "log", "cosine-log"}) {
    SCOPED_TRACE(name);
    const LayoutTransform layout = LayoutTransform::parse(name);
    const auto g = [&](double x) {
      switch (layout.map) {
        case LayoutTransform::Map::linear: return x;
        case LayoutTransform::Map::cube_root: return std::cbrt(x);
        case LayoutTransform::Map::log: return std::log1p(100.0 * x);
      }
      return x;
    };
    std::vector<double> centred(rows * ld, -7.0);
    std::vector<float> transformed(rows * ld, -7.0f);
    centre_and_transform_kept(values, runs.range(0), mean.data(), centred.data(), layout, cosine.data(),
                              transformed.data(), ld);
    std::size_t out = 0;
    for (Eigen::Index j = 0; j < columns; ++j) {
      if (!kept[static_cast<std::size_t>(j)]) continue;
      const double w = layout.cosine_weighted ? cosine[static_cast<std::size_t>(j)] : 1.0;
      double own = 0.0;
      for (Eigen::Index i = 0; i < rows; ++i) own += g(values(i, j)) * w / static_cast<double>(rows);
      for (Eigen::Index i = 0; i < rows; ++i) {
        const std::size_t at = static_cast<std::size_t>(i) * ld + out;
        EXPECT_EQ(centred[at], values(i, j) - mean[static_cast<std::size_t>(j)]);
        const double want = g(values(i, j)) * w - own;
        EXPECT_NEAR(transformed[at], want, 2e-6 * (std::abs(g(values(i, j)) * w) + 1e-3));
      }
      ++out;
    }
    for (Eigen::Index i = 0; i < rows; ++i)
      for (std::size_t k = runs.kept; k < ld; ++k) {
        EXPECT_EQ(centred[static_cast<std::size_t>(i) * ld + k], -7.0);
        EXPECT_EQ(transformed[static_cast<std::size_t>(i) * ld + k], -7.0f);
      }
  }
}

}  // namespace
}  // namespace matlas
