#pragma once
// Centring a column block over the materials (the pass of a build). Both steps work on a
// column range meant to fit in cache, reading each row's part of the range contiguously.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "manifold/column_blocks.h"

namespace matlas {

/// mean[first, last) = the mean over the materials of each kept column, 0 for dropped columns.
void kept_column_means(const BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                       std::size_t last, double* mean);

/// Subtracts the means from the kept columns in [first, last) and sets dropped columns to 0 (so
/// they add nothing to Gram matrices).
void subtract_column_means(BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                           std::size_t last, const double* mean);

}  // namespace matlas
