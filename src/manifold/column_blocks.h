#pragma once
// Streaming over a MaterialSet in column blocks: the n x D data matrix (one row per material,
// D = 3 * bins values in physical units) is visited a block of columns at a time, so memory never
// holds more than one block of all n materials. Every pass of a build, the evaluation and the
// projection goes through here.
#include <cstddef>
#include <functional>

#include <Eigen/Core>

#include "core/progress.h"
#include "manifold/material_set.h"

namespace matlas {

/// One block: columns [first, first + values.cols()) of the data matrix.
struct ColumnBlock {
  std::size_t first = 0;
  /// n x count, physical units (stored * channel scale); entries where the material has no
  /// measurement are NaN-free but meaningless: check `measured`.
  Eigen::Ref<const Eigen::MatrixXd> values;
  /// count entries: true where every material has a measurement (the column is kept).
  const std::vector<bool>& kept;
};

struct BlockOptions {
  /// Columns per block (default: 32768, i.e. n * 256 KiB of doubles).
  std::size_t block_columns = 32768;
  /// Label for progress reporting.
  std::string label = "reading";
};

/// Calls visit(block) for consecutive blocks covering all columns, in order, from one thread
/// (the visitor may use parallel_for inside). Reading of the next block overlaps with the
/// visitor's work on the current one.
void for_each_column_block(const MaterialSet& set, const std::function<void(const ColumnBlock&)>& visit,
                           const BlockOptions& options = {}, ProgressSink& progress = null_progress());

}  // namespace matlas
