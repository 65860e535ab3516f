#include "manifold/gram.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "brdf/albedo_operator.h"
#include "core/error.h"
#include "core/parallel.h"
#include "manifold/block_centring.h"
#include "manifold/column_blocks.h"
#include "manifold/gram_update.h"

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

/// Albedo-operator entries touching a block: column j of the block contributes weight * value
/// to albedo slot (theta bin * 3 + channel).
struct AlbedoEntry {
  Eigen::Index column;
  Eigen::Index slot;
  double weight;
};

std::vector<AlbedoEntry> albedo_entries(const Eigen::SparseMatrix<double, Eigen::RowMajor>& op,
                                        std::size_t bins, std::size_t first, std::size_t count) {
  std::vector<AlbedoEntry> entries;
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t v = first + j, channel = v / bins;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(op, static_cast<Eigen::Index>(v % bins)); it; ++it)
      entries.push_back({static_cast<Eigen::Index>(j), it.col() * 3 + static_cast<Eigen::Index>(channel), it.value()});
  }
  return entries;
}

}  // namespace

GramResult accumulate_gram(const MaterialSet& set, const LayoutTransform& layout, std::size_t block_columns,
                           ProgressSink& progress, RawBlockVisitor* raw) {
  const auto n = static_cast<Eigen::Index>(set.size());
  const MerlDims dims = set.dims();
  const std::size_t bins = dims.bins();
  GramResult r;
  r.kept.assign(set.value_count(), false);
  r.gram = Eigen::MatrixXd::Zero(n, n);
  const bool separate_layout = !layout.is_identity();
  const bool linear_layout = layout.map == LayoutTransform::Map::linear;
  if (separate_layout) r.layout_gram = Eigen::MatrixXd::Zero(n, n);
  std::vector<double> mean;
  mean.reserve(set.value_count());

  const auto albedo_op = albedo_operator(dims, 90);
  const std::vector<double> cos_w = layout.cosine_weighted ? bin_cosine_factors(dims) : std::vector<double>{};

  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor albedo_centred = RowMajor::Zero(n, 90 * 3);
  Eigen::RowVectorXd albedo_of_mean = Eigen::RowVectorXd::Zero(90 * 3);
  BlockMatrix transformed;
  std::vector<double> block_mean, transformed_mean;
  std::vector<double> block_cos;  // cosine factor of each column of the current block
  BlockOptions options;
  options.block_columns = block_columns;
  options.label = "reading the inputs";
  options.hashes = &r.hashes;
  for_each_column_block(set, [&](const ColumnBlock& block) {
    const auto k = static_cast<std::size_t>(block.count);
    if (layout.cosine_weighted) {
      block_cos.resize(k);
      for (std::size_t j = 0; j < k; ++j) block_cos[j] = cos_w[(block.first + j) % bins];
    }
    block_mean.resize(k);
    if (separate_layout) transformed.resize(n, static_cast<Eigen::Index>(k));
    if (separate_layout && !linear_layout) transformed_mean.resize(k);
    if (raw) raw->prepare(block);
    // One sweep over cache-sized column ranges. The means are computed first: reading each
    // row's part of the range contiguously brings the range into cache for what follows (the
    // raw visitor, the layout transform, the centring).
    const std::size_t sweep = RawBlockVisitor::kSweepColumns;
    parallel_for_each(0, (k + sweep - 1) / sweep, [&](std::size_t c) {
      const std::size_t j0 = c * sweep, j1 = std::min(k, j0 + sweep);
      kept_column_means(block.values, block.kept, j0, j1, block_mean.data());
      if (raw) raw->visit(block, j0, j1);
      if (separate_layout && !linear_layout) {
        // Non-linear maps apply to the raw values; the result is centred on its own mean.
        for (Eigen::Index i = 0; i < n; ++i) {
          const double* in = block.values.row(i).data();
          double* out = transformed.row(i).data();
          for (std::size_t j = j0; j < j1; ++j) {
            const double x = layout.map == LayoutTransform::Map::cube_root ? fast_cbrt(in[j])
                                                                           : std::log1p(100.0 * std::max(in[j], 0.0));
            out[j] = layout.cosine_weighted ? x * block_cos[j] : x;
          }
        }
        kept_column_means(transformed, block.kept, j0, j1, transformed_mean.data());
        subtract_column_means(transformed, block.kept, j0, j1, transformed_mean.data());
      }
      subtract_column_means(block.values, block.kept, j0, j1, block_mean.data());
      if (separate_layout && linear_layout)  // a per-column factor commutes with centring
        for (Eigen::Index i = 0; i < n; ++i) {
          const double* in = block.values.row(i).data();
          double* out = transformed.row(i).data();
          for (std::size_t j = j0; j < j1; ++j) out[j] = in[j] * block_cos[j];
        }
    });
    if (raw) raw->finish(block);
    if (separate_layout) add_gram_upper(transformed, r.layout_gram);
    add_gram_upper(block.values, r.gram);
    for (std::size_t j = 0; j < block.count; ++j)
      if (block.kept[j]) {
        r.kept[block.first + j] = true;
        mean.push_back(block_mean[j]);
      }
    // Albedo curves are linear: A(z_i) = A(z_i - mean) + A(mean).
    const auto entries = albedo_entries(albedo_op, bins, block.first, block.count);
    parallel_for(0, static_cast<std::size_t>(n), [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) {
        const double* row = block.values.row(static_cast<Eigen::Index>(i)).data();
        double* out = albedo_centred.row(static_cast<Eigen::Index>(i)).data();
        for (const AlbedoEntry& e : entries) out[e.slot] += e.weight * row[e.column];
      }
    });
    for (const AlbedoEntry& e : entries) albedo_of_mean[e.slot] += e.weight * block_mean[static_cast<std::size_t>(e.column)];
  }, options, progress);
  r.albedo = albedo_centred.rowwise() + albedo_of_mean;

  r.kept_columns = mean.size();
  if (r.kept_columns == 0)
    throw Error("no column is measured in every material: the inputs have no common measurements");
  r.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  symmetrize_from_upper(r.gram);
  if (separate_layout) symmetrize_from_upper(r.layout_gram);
  else r.layout_gram = r.gram;
  return r;
}

}  // namespace matlas
