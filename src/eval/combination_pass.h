#pragma once
// One streaming pass over a MaterialSet that evaluates many affine combinations of its tables
// ("items": item k is sum_i C(k, i) z_i) and accumulates distances between pairs of items, plus
// per-item counts of negative values. Every perceptual number of the evaluation (leave-one-out
// reconstructions, PCA and nearest-material baselines, samples along latent paths, map grids)
// comes from one such pass: the tables are read once, never held whole.
#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/communicator.h"
#include "core/progress.h"
#include "eval/brdf_distance.h"
#include "manifold/gram.h"
#include "manifold/material_set.h"

namespace matlas::eval {

struct CombinationQuery {
  /// m x n raw coefficients: item k = sum_i coefficients(k, i) z_i (rows normally sum to 1).
  Eigen::MatrixXd coefficients;
  /// Item pairs whose distances are wanted.
  std::vector<std::pair<int, int>> pairs;
  /// Use every value_stride-th value only (1 = all): a deterministic subsample for quick runs.
  int value_stride = 1;
  /// Pairs of two different items among the first `gram_items` are summed through those items'
  /// Gram matrices, |a|^2 + |b|^2 - 2 a.b by BLAS (k^2 J / 2 multiply-adds per block at the
  /// cores' full rate), instead of one difference per pair and value: for all pairs of n
  /// materials, n^2 / 2 of them. Meant for items whose distances are not tiny against their norms
  /// (distinct materials: the rounding is ~1e-16 of the norms, below 1e-9 of such distances); a
  /// squared distance below 1e-12 of the squared norms is 0 (two copies of a table are at 0).
  /// 0: every pair by differences.
  int gram_items = 0;
  /// Upper bound on the memory of the per-block item values (bytes); sets the block size.
  std::size_t memory_budget = std::size_t{256} << 20;
  /// Which values this process reads: share `part` of `parts` contiguous shares of the value
  /// indices (a pass split across ranks, whose sums reduce_combinations then adds up).
  PassShare share{};
};

struct CombinationResult {
  std::vector<BrdfDistance> distances;    ///< one per query pair
  std::vector<std::size_t> negatives;     ///< per item: compared values below 0
  std::size_t values = 0;                 ///< values compared per item (kept, above the horizon)
  std::vector<DistanceSums> sums;         ///< one per query pair: what `distances` is finished from
};

/// Runs the pass. Only values kept by the set (measured in every material) with a positive cosine
/// factor are used. Throws matlas::Error on a malformed query.
CombinationResult evaluate_combinations(const MaterialSet& set, const CombinationQuery& query,
                                        ProgressSink& progress = null_progress());

/// Adds up the ranks' results of their shares (sums, negatives, values; Communicator::sum in
/// double: exact for the counts below 2^53) and finishes the distances again: afterwards every
/// rank holds the whole pass's result, the same to rounding as one process's.
void reduce_combinations(CombinationResult& result, Communicator& comm);

}  // namespace matlas::eval
