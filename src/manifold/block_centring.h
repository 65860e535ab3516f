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

/// mean[first, last) from the column sums of row groups: sums[g * stride + j] is group g's sum of
/// column j; the groups are added in order. n rows in all; 0 for dropped columns.
void column_means_from_sums(const double* sums, std::size_t stride, std::size_t groups,
                            const std::uint8_t* kept, std::size_t first, std::size_t last, std::size_t n,
                            double* mean);

/// subtract_column_means, and also weighted[i, j] = centred[i, j] * weight[j] (same shape as
/// values), in one pass over the range.
void centre_and_weight(BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                       std::size_t last, const double* mean, const double* weight, BlockMatrix& weighted);

}  // namespace matlas
