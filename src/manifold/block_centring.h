#pragma once
// Centring a column block over the materials, compacting out the dropped columns (the pass of a
// build). The steps work on a column range meant to fit in cache, reading each row's part of the
// range contiguously. Output blocks are row-major with row stride `ld` (n rows, compacted
// columns).
#include <cstddef>
#include <cstdint>
#include <span>

#include "manifold/column_blocks.h"
#include "manifold/kept_runs.h"

namespace matlas {

/// mean[first, last) from the column sums of row groups: sums[g * stride + j] is group g's sum of
/// column j; the groups are added in order. n rows in all; 0 for dropped columns.
void column_means_from_sums(const double* sums, std::size_t stride, std::size_t groups,
                            const std::uint8_t* kept, std::size_t first, std::size_t last, std::size_t n,
                            double* mean);

/// For the kept columns of `runs`: centred[i, out] = values[i, j] - mean[j] and, when weighted is
/// not null, weighted[i, out] = float(centred[i, out] * weight[j]) (a per-column factor commutes
/// with centring; the weighted copy feeds the layout's single-precision Gram, manifold/gram.h).
void centre_kept(const BlockMatrix& values, std::span<const KeptRun> runs, const double* mean,
                 double* centred, const float* weight, float* weighted, std::size_t ld);

}  // namespace matlas
