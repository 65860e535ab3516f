#pragma once
// Centring a column block over the materials (the pass of a build).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "manifold/column_blocks.h"

namespace matlas {

/// Subtracts from every kept column in [first, last) its mean over the materials and sets
/// dropped columns to 0 (so they add nothing to Gram matrices). Writes the means to
/// mean[first, last) (0 for dropped columns). Meant for ranges that fit in cache: the range is
/// read twice.
void centre_kept_columns(BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                         std::size_t last, double* mean);

}  // namespace matlas
