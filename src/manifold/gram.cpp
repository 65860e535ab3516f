#include "manifold/gram.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>

#include "brdf/albedo_operator.h"
#include "core/communicator.h"
#include "core/error.h"
#include "core/huge_pages.h"
#include "core/parallel.h"
#include "manifold/block_centring.h"
#include "manifold/block_prefetch.h"
#include "manifold/block_rows.h"
#include "manifold/column_blocks.h"
#include "manifold/gram_update.h"
#include "manifold/kept_runs.h"
#include "manifold/model_format.h"
#include "manifold/read_ahead.h"

namespace matlas {

namespace {

/// Materials read per task of a block (their column sums are added up in a fixed order, so the
/// mean does not depend on the thread count). 10 tasks for n = 100: fewer, larger tasks than
/// with 4 materials each took the read step from 0.37 to 0.32 s; 25 each balanced worse.
constexpr std::size_t kReadRows = 10;
/// Materials per albedo task.
constexpr std::size_t kAlbedoRows = 25;
/// Files not in the page cache: the read-ahead thread keeps the disk kReadAheadValues values of
/// every file (2 MB) ahead of the pass, asking for kReadAheadChunk values (256 KB) at a time, or
/// a block at a time when blocks are wider. In values, not blocks: the window (2 GB of page cache
/// at n = 1000) does not grow with the block width.
constexpr std::size_t kReadAheadValues = std::size_t{1} << 18, kReadAheadChunk = std::size_t{1} << 15;

using SparseOperator = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// Albedo-operator entries touching a block: a column contributes weight * value to albedo slot
/// (theta bin * 3 + channel).
struct AlbedoEntry {
  Eigen::Index column;        ///< in the compacted block
  Eigen::Index slot;
  double weight;
  std::size_t block_column;  ///< the same column in the block
};

/// The albedo-operator entries of a block's kept columns.
std::vector<AlbedoEntry> albedo_entries(const SparseOperator& op, std::size_t bins, std::size_t first,
                                        const KeptRuns& kept) {
  std::vector<AlbedoEntry> entries;
  for (const KeptRun& run : kept.runs)
    for (std::size_t j = 0; j < run.count; ++j) {
      const std::size_t v = first + run.first + j, channel = v / bins;
      for (SparseOperator::InnerIterator it(op, static_cast<Eigen::Index>(v % bins)); it; ++it)
        entries.push_back({static_cast<Eigen::Index>(run.out + j), it.col() * 3 + static_cast<Eigen::Index>(channel),
                           it.value(), run.first + j});
    }
  return entries;
}

/// The state of one pass and its three steps per block. Everything per block (the block, the
/// group sums, the compacted centred and transformed columns) is allocated once and stays in
/// the last-level cache between the steps.
class Pass {
public:
  Pass(const MaterialSet& set, const LayoutTransform& layout, std::size_t block_columns, RawBlockVisitor* raw,
       PassShare share, PassReads reads)
      : set_(set), layout_(layout), raw_(raw), reads_(reads), n_(set.size()), bins_(set.dims().bins()),
        total_(set.value_count()), step_(std::max<std::size_t>(1, std::min(block_columns, total_))),
        blocks_(share_of((total_ + step_ - 1) / step_, share.part, share.parts)), whole_(share.parts == 1),
        groups_((n_ + kReadRows - 1) / kReadRows), separate_layout_(!layout.is_identity()),
        albedo_op_(albedo_operator(set.dims(), kAlbedoAngles)),
        cosine_(layout.cosine_weighted ? bin_cosine_factors(set.dims()) : std::vector<double>{}), hashers_(n_),
        values_(static_cast<Eigen::Index>(n_), static_cast<Eigen::Index>(step_)), group_sums_(groups_ * step_),
        group_kept_(groups_ * step_), centred_(n_ * step_), transformed_(separate_layout_ ? n_ * step_ : 0),
        block_mean_(step_), block_cos_(layout.cosine_weighted ? step_ : 0),
        linear_gram_(static_cast<Eigen::Index>(n_), step_),
        layout_gram_(static_cast<Eigen::Index>(n_), separate_layout_ ? step_ : 1),
        albedo_centred_(RowMajor::Zero(static_cast<Eigen::Index>(n_), kAlbedoAngles * 3)),
        albedo_of_mean_(Eigen::RowVectorXd::Zero(kAlbedoAngles * 3)) {
    advise_block();
    result_.kept.assign(total_, false);
    result_.first_value = std::min(total_, first_of(blocks_.first));
    result_.end_value = std::min(total_, first_of(blocks_.second));
    mean_.reserve(result_.end_value - result_.first_value);
  }

  /// Block b+1 is read while block b's products are computed, in the same parallel region: the
  /// reads (uniform tasks) fill the gaps the uneven product tasks leave on the cores, and the
  /// pass has two barriers per block instead of three.
  GramResult run(ProgressSink& progress) {
    const std::size_t b0 = blocks_.first;  // not a structured binding: clang 14 cannot capture one
    const std::size_t blocks = blocks_.second;
    ProgressTask task(progress, whole_ ? "reading the inputs" : "reading this rank's share of the inputs",
                      blocks - b0);
    if (b0 == blocks) return finish();  // a share with no block (more ranks than blocks)
    auto start = std::chrono::steady_clock::now();
    const auto lap = [&start](double& seconds) {
      const auto now = std::chrono::steady_clock::now();
      seconds += std::chrono::duration<double>(now - start).count();
      start = now;
    };
    // A share larger than the machine's memory is read ahead around the page cache
    // (manifold/block_prefetch.h); a smaller one through it, the disk asked a window ahead
    // (manifold/read_ahead.h), and where page_cache reads are asked for a larger share, what has
    // been read leaves the cache first.
    const bool larger = ReadAhead::worth_releasing(n_ * (result_.end_value - result_.first_value) * sizeof(double));
    std::optional<ReadAhead> ahead;
    if (reads_ == PassReads::prefetch || (reads_ == PassReads::automatic && larger)) {
      prefetch_ = std::make_unique<BlockPrefetch>(set_, step_, b0, blocks);
    } else {
      ahead.emplace([this](std::size_t first, std::size_t count) { set_.prefetch(first, count); },
                    result_.first_value, result_.end_value, std::max(kReadAheadValues, 2 * step_),
                    std::max(kReadAheadChunk, step_),
                    larger ? ReadAhead::Request([this](std::size_t first, std::size_t count) { set_.release(first, count); })
                           : nullptr);
    }
    begin_read(b0);
    parallel_for_each(0, groups_, [&](std::size_t g) { read_group(b0, g); });
    end_read(b0);
    lap(result_.steps.read);
    for (std::size_t b = b0; b < blocks; ++b) {
      const ColumnBlock block{first_of(b), count_of(b), values_, kept_};
      const KeptRuns runs = kept_runs(kept_.data(), block.count, RawBlockVisitor::kSweepColumns);
      sweep(block, runs);
      lap(result_.steps.sweep);
      const bool next = b + 1 < blocks;
      if (ahead) ahead->advance(first_of(b + 1));
      if (next) begin_read(b + 1);
      products(block, runs, next ? b + 1 : kNoBlock);
      lap(result_.steps.products);
      if (next) end_read(b + 1);
      lap(result_.steps.read);
      task.advance();
    }
    return finish();
  }

private:
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  static constexpr std::size_t kNoBlock = static_cast<std::size_t>(-1);

  std::size_t first_of(std::size_t b) const { return b * step_; }
  std::size_t count_of(std::size_t b) const { return std::min(step_, total_ - b * step_); }

  /// 1. Reads block b, a few materials per task (read_group): hash, check, scale, and per group
  ///    of materials the column sums and validity; then (end_read) which columns every material
  ///    measures. The disk is asked for the blocks ahead by the read-ahead thread (run).
  void begin_read(std::size_t b) {
    if (count_of(b) != static_cast<std::size_t>(values_.cols())) {  // the last block
      values_.resize(static_cast<Eigen::Index>(n_), static_cast<Eigen::Index>(count_of(b)));
      advise_block();
    }
  }

  /// Huge pages for the block (fresh memory, not yet touched): every read and sweep walks it; with
  /// the pass's other buffers in 4 KiB pages the 1000-material build took seconds longer on a
  /// virtual machine (docs/BENCHMARKS.md, "Huge pages for the pass's buffers").
  void advise_block() { advise_huge_pages(values_.data(), static_cast<std::size_t>(values_.size()) * sizeof(double)); }

  void read_group(std::size_t b, std::size_t g) {
    const std::size_t first = first_of(b), count = count_of(b);
    const std::size_t r0 = g * kReadRows, r1 = std::min(n_, r0 + kReadRows);
    read_block_rows(set_, first, count, r0, r1, values_, hashers_.data(),
                    {group_sums_.data() + g * step_, group_kept_.data() + g * step_}, {prefetch_.get(), b});
  }

  void end_read(std::size_t b) {
    if (prefetch_) prefetch_->done(b);  // every row of block b is in values_
    const std::size_t first = first_of(b), count = count_of(b);
    kept_.assign(count, 1);
    for (std::size_t g = 0; g < groups_; ++g) {
      const std::uint8_t* k = group_kept_.data() + g * step_;
      for (std::size_t j = 0; j < count; ++j) kept_[j] &= k[j];
    }
    if (layout_.cosine_weighted)
      for (std::size_t j = 0, bin = first % bins_; j < count; ++j, bin = bin + 1 == bins_ ? 0 : bin + 1)
        block_cos_[j] = static_cast<float>(cosine_[bin]);
  }

  /// 2. One sweep over cache-sized column ranges: the means, the raw visitor, then the kept
  ///    columns centred (and transformed) into the compacted blocks.
  void sweep(const ColumnBlock& block, const KeptRuns& runs) {
    if (raw_) raw_->prepare(block);
    const std::size_t range = RawBlockVisitor::kSweepColumns;
    parallel_for_each(0, (block.count + range - 1) / range, [&](std::size_t c) {
      const std::size_t j0 = c * range, j1 = std::min(block.count, j0 + range);
      column_means_from_sums(group_sums_.data(), step_, groups_, kept_.data(), j0, j1, n_, block_mean_.data());
      if (raw_) raw_->visit(block, j0, j1);
      const std::span<const KeptRun> kept = runs.range(c);
      if (!separate_layout_) {
        centre_kept(values_, kept, block_mean_.data(), centred_.data(), nullptr, nullptr, step_);
      } else if (layout_.map == LayoutTransform::Map::linear) {  // a per-column factor commutes with centring
        centre_kept(values_, kept, block_mean_.data(), centred_.data(), block_cos_.data(), transformed_.data(), step_);
      } else {  // non-linear maps apply to the raw values, then are centred on their own means
        centre_and_transform_kept(values_, kept, block_mean_.data(), centred_.data(), layout_, block_cos_.data(),
                                  transformed_.data(), step_);
      }
    });
  }

  /// 3. The Gram slices of the compacted blocks, the albedo curves (linear: A(z_i) =
  ///    A(z_i - mean) + A(mean)) and the raw visitor's output, all independent, on the workers;
  ///    with them, the groups of block `next` are read into values_ (which nothing here reads).
  void products(const ColumnBlock& block, const KeptRuns& runs, std::size_t next) {
    const auto entries = albedo_entries(albedo_op_, bins_, block.first, runs);
    const std::size_t slices = GramAccumulator::slices(runs.kept);
    const std::size_t gram_tasks = separate_layout_ ? 2 * slices : slices;
    const std::size_t albedo_tasks = (n_ + kAlbedoRows - 1) / kAlbedoRows;
    const std::size_t own_tasks = gram_tasks + albedo_tasks + (raw_ ? 1 : 0);
    const std::size_t read_tasks = next == kNoBlock ? 0 : groups_;
    parallel_for_each(0, own_tasks + read_tasks, [&](std::size_t t) {
      if (t < slices) {
        linear_gram_.add_slice(centred_.data(), step_, runs.kept, t);
      } else if (t < gram_tasks) {
        layout_gram_.add_slice(transformed_.data(), step_, runs.kept, t - slices);
      } else if (t < gram_tasks + albedo_tasks) {
        const std::size_t r0 = (t - gram_tasks) * kAlbedoRows, r1 = std::min(n_, r0 + kAlbedoRows);
        for (std::size_t i = r0; i < r1; ++i) {
          const double* row = centred_.data() + i * step_;
          double* out = albedo_centred_.row(static_cast<Eigen::Index>(i)).data();
          for (const AlbedoEntry& e : entries) out[e.slot] += e.weight * row[e.column];
        }
      } else if (t < own_tasks) {
        raw_->finish(block);
      } else {
        read_group(next, t - own_tasks);
      }
    });
    for (const AlbedoEntry& e : entries) albedo_of_mean_[e.slot] += e.weight * block_mean_[e.block_column];
    for (std::size_t j = 0; j < block.count; ++j)
      if (kept_[j]) {
        result_.kept[block.first + j] = true;
        mean_.push_back(block_mean_[j]);
      }
  }

  GramResult finish() {
    result_.kept_columns = mean_.size();
    if (whole_) require_kept_columns(result_);
    result_.hashes = hashers_.digests();
    result_.albedo = albedo_centred_.rowwise() + albedo_of_mean_;
    result_.mean = Eigen::Map<const Eigen::VectorXd>(mean_.data(), static_cast<Eigen::Index>(mean_.size()));
    linear_gram_.total(result_.gram, result_.gram_low);
    if (separate_layout_) {
      layout_gram_.total(result_.layout_gram, result_.layout_gram_low);
    } else {
      result_.layout_gram = result_.gram;
      result_.layout_gram_low = result_.gram_low;
    }
    return std::move(result_);
  }

  const MaterialSet& set_;
  const LayoutTransform layout_;
  RawBlockVisitor* const raw_;
  const PassReads reads_;
  const std::size_t n_, bins_, total_, step_;
  const std::pair<std::size_t, std::size_t> blocks_;  ///< the share's blocks [first, second)
  const bool whole_;                                  ///< the share is the whole pass
  const std::size_t groups_;
  const bool separate_layout_;
  const SparseOperator albedo_op_;
  const std::vector<double> cosine_;  ///< per bin, when cosine-weighted
  FileHashers hashers_;

  BlockMatrix values_;                    ///< the block, physical units, as read
  HugePageVector<double> group_sums_;     ///< per group of kReadRows materials, column sums
  std::vector<std::uint8_t> group_kept_;  ///< per group, the columns all its materials measure
  std::vector<std::uint8_t> kept_;        ///< the columns every material measures
  HugePageVector<double> centred_;        ///< kept columns, centred, compacted (row stride step_)
  HugePageVector<float> transformed_;     ///< the same through the layout transform, single precision
  std::vector<double> block_mean_;        ///< per block column (0 where dropped)
  std::vector<float> block_cos_;          ///< per block column, when cosine-weighted
  GramAccumulator linear_gram_, layout_gram_;
  RowMajor albedo_centred_;
  Eigen::RowVectorXd albedo_of_mean_;
  std::vector<double> mean_;  ///< per kept column so far
  GramResult result_;
  std::unique_ptr<BlockPrefetch> prefetch_;  ///< when the pass reads ahead around the page cache
};

}  // namespace

std::size_t default_block_columns(std::size_t n) {
  constexpr std::size_t kNarrow = 4096, kWide = 16384, kManyFiles = 512, kMaxBlockBytes = std::size_t{256} << 20;
  if (n < kManyFiles) return kNarrow;
  const std::size_t fitting = kMaxBlockBytes / (n * sizeof(double)) / GramAccumulator::kSlice * GramAccumulator::kSlice;
  return std::clamp(fitting, kNarrow, kWide);
}

GramResult accumulate_gram(const MaterialSet& set, const LayoutTransform& layout, std::size_t block_columns,
                           ProgressSink& progress, RawBlockVisitor* raw, PassShare share, PassReads reads) {
  return Pass(set, layout, resolved_block_columns(block_columns, set.size()), raw, share, reads).run(progress);
}

void require_kept_columns(const GramResult& g) {
  if (g.kept_columns == 0)
    throw Error("no column is measured in every material: the inputs have no common measurements");
}

}  // namespace matlas
