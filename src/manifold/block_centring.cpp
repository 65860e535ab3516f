#include "manifold/block_centring.h"

#include <algorithm>

#include "core/simd_clones.h"

namespace matlas {

namespace {

/// Columns per stack-held mask of the centring loops.
constexpr std::size_t kMaskChunk = 512;

/// mask[j] = 1.0 for kept columns, 0.0 for dropped ones: centring then multiplies by the mask
/// instead of branching per value, which vectorises (values are finite, so dropped columns become
/// exact zeros).
void keep_mask(const std::uint8_t* kept, std::size_t len, double* mask) {
  for (std::size_t j = 0; j < len; ++j) mask[j] = kept[j] ? 1.0 : 0.0;
}

}  // namespace

MATLAS_SIMD_CLONES void kept_column_means(const BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                       std::size_t last, double* mean) {
  const Eigen::Index n = values.rows();
  const std::size_t len = last - first;
  double* m = mean + first;
  std::fill(m, m + len, 0.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* row = values.row(i).data() + first;
    for (std::size_t j = 0; j < len; ++j) m[j] += row[j];
  }
  const double inv_n = 1.0 / static_cast<double>(n);
  for (std::size_t j = 0; j < len; ++j) m[j] = kept[first + j] ? m[j] * inv_n : 0.0;
}

MATLAS_SIMD_CLONES void subtract_column_means(BlockMatrix& values, const std::vector<std::uint8_t>& kept,
                                              std::size_t first, std::size_t last, const double* mean) {
  for (std::size_t j0 = first; j0 < last; j0 += kMaskChunk) {
    const std::size_t len = std::min(kMaskChunk, last - j0);
    double mask[kMaskChunk];
    keep_mask(kept.data() + j0, len, mask);
    const double* __restrict m = mean + j0;
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      double* __restrict row = values.row(i).data() + j0;
      for (std::size_t j = 0; j < len; ++j) row[j] = (row[j] - m[j]) * mask[j];
    }
  }
}

MATLAS_SIMD_CLONES void column_means_from_sums(const double* sums, std::size_t stride, std::size_t groups,
                            const std::uint8_t* kept, std::size_t first, std::size_t last, std::size_t n,
                            double* mean) {
  double* __restrict m = mean + first;
  const std::size_t len = last - first;
  std::fill(m, m + len, 0.0);
  for (std::size_t g = 0; g < groups; ++g) {
    const double* __restrict s = sums + g * stride + first;
    for (std::size_t j = 0; j < len; ++j) m[j] += s[j];
  }
  const double inv_n = 1.0 / static_cast<double>(n);
  for (std::size_t j = 0; j < len; ++j) m[j] = kept[first + j] ? m[j] * inv_n : 0.0;
}

MATLAS_SIMD_CLONES void centre_and_weight(BlockMatrix& values, const std::vector<std::uint8_t>& kept,
                                          std::size_t first, std::size_t last, const double* mean,
                                          const double* weight, BlockMatrix& weighted) {
  for (std::size_t j0 = first; j0 < last; j0 += kMaskChunk) {
    const std::size_t len = std::min(kMaskChunk, last - j0);
    double mask[kMaskChunk];
    keep_mask(kept.data() + j0, len, mask);
    const double* __restrict m = mean + j0;
    const double* __restrict w = weight + j0;
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      double* __restrict row = values.row(i).data() + j0;
      double* __restrict out = weighted.row(i).data() + j0;
      for (std::size_t j = 0; j < len; ++j) {
        const double c = (row[j] - m[j]) * mask[j];
        row[j] = c;
        out[j] = c * w[j];
      }
    }
  }
}

}  // namespace matlas
