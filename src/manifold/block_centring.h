#pragma once
// Centring a column block over the materials, shared by both passes of a build.
#include <cstdint>
#include <vector>

#include "manifold/column_blocks.h"

namespace matlas {

/// Subtracts from every kept column its mean over the materials and sets dropped columns to 0
/// (so they add nothing to Gram matrices). Returns the means in `mean` (0 for dropped columns).
/// Rows are contiguous, so every step runs over contiguous memory.
void centre_kept_columns(BlockMatrix& values, const std::vector<std::uint8_t>& kept,
                         Eigen::RowVectorXd& mean);

}  // namespace matlas
