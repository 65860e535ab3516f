#include "manifold/gram.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "brdf/albedo_operator.h"
#include "core/error.h"
#include "core/parallel.h"
#include "manifold/block_centring.h"
#include "manifold/block_rows.h"
#include "manifold/column_blocks.h"
#include "manifold/gram_update.h"
#include "manifold/kept_runs.h"

namespace matlas {

std::string LayoutTransform::to_string() const {
  const char* map_name = map == Map::linear ? "linear" : map == Map::cube_root ? "cbrt" : "log";
  return cosine_weighted ? std::string("cosine-") + map_name : std::string(map_name);
}

LayoutTransform LayoutTransform::parse(const std::string& name) {
  LayoutTransform t;
  std::string rest = name;
  if (rest.rfind("cosine-", 0) == 0) {
    t.cosine_weighted = true;
    rest = rest.substr(7);
  } else if (rest == "cosine") {
    t.cosine_weighted = true;
    rest = "linear";
  }
  if (rest == "linear") t.map = Map::linear;
  else if (rest == "cbrt") t.map = Map::cube_root;
  else if (rest == "log") t.map = Map::log;
  else
    throw Error("unknown layout transform '" + name +
                "' (expected linear, cbrt or log, optionally prefixed with cosine-)");
  return t;
}

namespace {

/// Cube root to ~1e-9 relative error, several times faster than std::cbrt: an exponent-based
/// first guess refined by Newton steps. Only used to place latent points.
inline double fast_cbrt(double x) {
  if (x <= 0.0) return x == 0.0 ? 0.0 : -fast_cbrt(-x);
  double y = std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) / 3 + 0x2A9F7893782DA1CEull);
  for (int k = 0; k < 4; ++k) y = y - (y * y * y - x) / (3.0 * y * y);
  return y;
}

/// Albedo-operator entries touching a block: a column contributes weight * value to albedo slot
/// (theta bin * 3 + channel).
struct AlbedoEntry {
  Eigen::Index column;        ///< in the compacted block
  Eigen::Index slot;
  double weight;
  std::size_t block_column;  ///< the same column in the block
};

/// The albedo-operator entries of a block's kept columns, by compacted column.
std::vector<AlbedoEntry> albedo_entries(const Eigen::SparseMatrix<double, Eigen::RowMajor>& op,
                                        std::size_t bins, std::size_t first, const KeptRuns& kept) {
  std::vector<AlbedoEntry> entries;
  for (const KeptRun& run : kept.runs)
    for (std::size_t j = 0; j < run.count; ++j) {
      const std::size_t v = first + run.first + j, channel = v / bins;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(op, static_cast<Eigen::Index>(v % bins)); it; ++it)
        entries.push_back({static_cast<Eigen::Index>(run.out + j), it.col() * 3 + static_cast<Eigen::Index>(channel),
                           it.value(), run.first + j});
    }
  return entries;
}

/// Materials read per task of a block (their column sums are added up in a fixed order, so the
/// mean does not depend on the thread count).
constexpr std::size_t kReadRows = 4;
/// Materials per albedo task.
constexpr std::size_t kAlbedoRows = 25;
/// Blocks asked of the disk at a time, that many blocks ahead (for files not in the page cache).
constexpr std::size_t kPrefetchBlocks = 32;

}  // namespace

GramResult accumulate_gram(const MaterialSet& set, const LayoutTransform& layout, std::size_t block_columns,
                           ProgressSink& progress, RawBlockVisitor* raw) {
  const std::size_t n = set.size();
  const auto rows = static_cast<Eigen::Index>(n);
  const MerlDims dims = set.dims();
  const std::size_t bins = dims.bins(), total = set.value_count();
  const std::size_t step = std::max<std::size_t>(1, std::min(block_columns, total));
  const std::size_t blocks = (total + step - 1) / step;
  const std::size_t groups = (n + kReadRows - 1) / kReadRows;
  const bool separate_layout = !layout.is_identity();
  const bool linear_layout = layout.map == LayoutTransform::Map::linear;

  GramResult r;
  r.kept.assign(total, false);
  std::vector<double> mean;
  mean.reserve(total);
  const auto albedo_op = albedo_operator(dims, 90);
  const std::vector<double> cos_w = layout.cosine_weighted ? bin_cosine_factors(dims) : std::vector<double>{};
  FileHashers hashers(n);

  // The block and what is derived from it stay in the last-level cache between the steps.
  BlockMatrix values(rows, static_cast<Eigen::Index>(step));
  std::vector<double> group_sums(groups * step);        // per group of kReadRows materials, column sums
  std::vector<std::uint8_t> group_kept(groups * step);  // per group, columns all its materials measure
  // The centred (and the transformed) kept columns, compacted: rows of stride `step`.
  std::vector<double> centred(n * step), transformed(separate_layout ? n * step : 0);
  std::vector<double> block_mean(step);
  std::vector<std::uint8_t> kept(step);
  std::vector<double> block_cos(layout.cosine_weighted ? step : 0);
  GramAccumulator linear_gram(rows, step), layout_gram(rows, separate_layout ? step : 1);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor albedo_centred = RowMajor::Zero(rows, 90 * 3);
  Eigen::RowVectorXd albedo_of_mean = Eigen::RowVectorXd::Zero(90 * 3);

  const SingleThreadedBlas single_threaded_blas;
  ProgressTask task(progress, "reading the inputs", blocks);

  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t first = b * step, count = std::min(step, total - first);
    if (count != static_cast<std::size_t>(values.cols())) values.resize(rows, static_cast<Eigen::Index>(count));

    auto step_start = std::chrono::steady_clock::now();
    const auto lap = [&step_start](double& seconds) {
      const auto now = std::chrono::steady_clock::now();
      seconds += std::chrono::duration<double>(now - step_start).count();
      step_start = now;
    };

    // 1. Read the block, a few materials per task: hash, check, scale, and per group of materials
    //    the column sums and validity. Cold files: ask for the blocks ahead every kPrefetchBlocks.
    parallel_for_each(0, groups, [&](std::size_t g) {
      const std::size_t r0 = g * kReadRows, r1 = std::min(n, r0 + kReadRows);
      if (b % kPrefetchBlocks == 0)
        for (std::size_t i = r0; i < r1; ++i) set.file(i).prefetch(first + kPrefetchBlocks * step, kPrefetchBlocks * step);
      read_block_rows(set, first, count, r0, r1, values, hashers.data(),
                      {group_sums.data() + g * step, group_kept.data() + g * step});
    });
    lap(r.steps.read);
    kept.resize(count);
    std::fill(kept.begin(), kept.end(), std::uint8_t{1});
    for (std::size_t g = 0; g < groups; ++g) {
      const std::uint8_t* k = group_kept.data() + g * step;
      for (std::size_t j = 0; j < count; ++j) kept[j] &= k[j];
    }
    if (layout.cosine_weighted)
      for (std::size_t j = 0, bin = first % bins; j < count; ++j, bin = bin + 1 == bins ? 0 : bin + 1)
        block_cos[j] = cos_w[bin];
    const ColumnBlock block{first, count, values, kept};

    // 2. One sweep over cache-sized column ranges: the means, the raw visitor, then the kept
    //    columns centred (and transformed) into the compacted blocks.
    if (raw) raw->prepare(block);
    const std::size_t sweep = RawBlockVisitor::kSweepColumns;
    const KeptRuns runs = kept_runs(kept.data(), count, sweep);
    parallel_for_each(0, (count + sweep - 1) / sweep, [&](std::size_t c) {
      const std::size_t j0 = c * sweep, j1 = std::min(count, j0 + sweep);
      column_means_from_sums(group_sums.data(), step, groups, kept.data(), j0, j1, n, block_mean.data());
      if (raw) raw->visit(block, j0, j1);
      const std::span<const KeptRun> range = runs.range(c);
      if (separate_layout && linear_layout) {
        centre_kept(values, range, block_mean.data(), centred.data(), block_cos.data(), transformed.data(), step);
        return;
      }
      centre_kept(values, range, block_mean.data(), centred.data(), nullptr, nullptr, step);
      if (separate_layout) {
        // Non-linear maps apply to the raw values; the result is centred on its own mean.
        for (std::size_t i = 0; i < n; ++i) {
          const double* in = values.row(static_cast<Eigen::Index>(i)).data();
          double* out = transformed.data() + i * step;
          for (const KeptRun& run : range)
            for (std::size_t j = run.first; j < run.first + run.count; ++j) {
              const double x = layout.map == LayoutTransform::Map::cube_root ? fast_cbrt(in[j])
                                                                             : std::log1p(100.0 * std::max(in[j], 0.0));
              out[run.out + j - run.first] = layout.cosine_weighted ? x * block_cos[j] : x;
            }
        }
        if (!range.empty())
          subtract_own_means(transformed.data(), n, step, range.front().out, range.back().out + range.back().count);
      }
    });
    lap(r.steps.sweep);

    // 3. The Gram slices of the compacted blocks, the albedo curves (linear: A(z_i) =
    //    A(z_i - mean) + A(mean)) and the raw visitor's output, all independent, on the workers.
    const auto entries = albedo_entries(albedo_op, bins, first, runs);
    const std::size_t slices = GramAccumulator::slices(runs.kept);
    const std::size_t gram_tasks = separate_layout ? 2 * slices : slices;
    const std::size_t albedo_tasks = (n + kAlbedoRows - 1) / kAlbedoRows;
    parallel_for_each(0, gram_tasks + albedo_tasks + (raw ? 1 : 0), [&](std::size_t t) {
      if (t < slices) {
        linear_gram.add_slice(centred.data(), step, runs.kept, t);
      } else if (t < gram_tasks) {
        layout_gram.add_slice(transformed.data(), step, runs.kept, t - slices);
      } else if (t < gram_tasks + albedo_tasks) {
        const std::size_t r0 = (t - gram_tasks) * kAlbedoRows, r1 = std::min(n, r0 + kAlbedoRows);
        for (std::size_t i = r0; i < r1; ++i) {
          const double* row = centred.data() + i * step;
          double* out = albedo_centred.row(static_cast<Eigen::Index>(i)).data();
          for (const AlbedoEntry& e : entries) out[e.slot] += e.weight * row[e.column];
        }
      } else {
        raw->finish(block);
      }
    });
    for (const AlbedoEntry& e : entries) albedo_of_mean[e.slot] += e.weight * block_mean[e.block_column];
    for (std::size_t j = 0; j < count; ++j)
      if (kept[j]) {
        r.kept[first + j] = true;
        mean.push_back(block_mean[j]);
      }
    lap(r.steps.products);
    task.advance();
  }

  r.hashes = hashers.digests();
  r.albedo = albedo_centred.rowwise() + albedo_of_mean;
  r.kept_columns = mean.size();
  if (r.kept_columns == 0)
    throw Error("no column is measured in every material: the inputs have no common measurements");
  r.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  r.gram = linear_gram.total();
  r.layout_gram = separate_layout ? layout_gram.total() : r.gram;
  return r;
}

}  // namespace matlas
