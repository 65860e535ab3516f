#pragma once
// Streaming over a MaterialSet in column blocks: the n x D data matrix (one row per material,
// D = 3 * bins values in physical units) is visited a block of columns at a time, so memory never
// holds more than one block of all n materials. The evaluation's passes over a database
// (`eval/model_checks.cpp`, `eval/combination_pass.cpp`) go through for_each_column_block. A
// build does not: its one pass is `Pass` in gram.cpp, which reads with read_block_rows
// (block_rows.h) in smaller cache-resident blocks, hashes the files as it reads and hands
// ColumnBlock views of its buffers to the raw-data visitors (gram.h).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "manifold/material_set.h"

namespace matlas {

/// Row-major n x count block: each material's values are contiguous.
using BlockMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// One block: columns [first, first + count) of the data matrix.
struct ColumnBlock {
  std::size_t first = 0;
  std::size_t count = 0;
  /// n x count, physical units (stored * channel scale). Where a material has no measurement
  /// the value is negative and meaningless: use `kept`. The visitor may modify the values in
  /// place (the buffer is refilled for the next block).
  BlockMatrix& values;
  /// count entries: 1 where every material has a measurement (the column is kept), else 0.
  const std::vector<std::uint8_t>& kept;
};

struct BlockOptions {
  /// Columns per block (default: 32768, i.e. n * 256 KiB of doubles; two blocks are in memory).
  std::size_t block_columns = 32768;
  /// Label for progress reporting.
  std::string label = "reading";
  /// The value indices the blocks cover, [first_value, end_value) clamped to the set's (one
  /// rank's share of a distributed pass); default: all of them.
  std::size_t first_value = 0, end_value = SIZE_MAX;
};

/// Calls visit(block) for consecutive blocks covering the columns of the options' range, in order, from one thread
/// (the visitor may use parallel_for inside). Reading of the next block overlaps with the
/// visitor's work on the current one.
void for_each_column_block(const MaterialSet& set, const std::function<void(const ColumnBlock&)>& visit,
                           const BlockOptions& options = {}, ProgressSink& progress = null_progress());

}  // namespace matlas
