#include "manifold/block_centring.h"

#include <algorithm>

#include "core/simd_clones.h"

namespace matlas {

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

MATLAS_SIMD_CLONES void subtract_column_means(BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                           std::size_t last, const double* mean) {
  const Eigen::Index n = values.rows();
  const std::size_t len = last - first;
  const double* m = mean + first;
  for (Eigen::Index i = 0; i < n; ++i) {
    double* row = values.row(i).data() + first;
    for (std::size_t j = 0; j < len; ++j) row[j] = kept[first + j] ? row[j] - m[j] : 0.0;
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

MATLAS_SIMD_CLONES void centre_and_weight(BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                       std::size_t last, const double* mean, const double* weight, BlockMatrix& weighted) {
  const std::size_t len = last - first;
  const double* __restrict m = mean + first;
  const double* __restrict w = weight + first;
  const std::uint8_t* __restrict k = kept.data() + first;
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    double* __restrict row = values.row(i).data() + first;
    double* __restrict out = weighted.row(i).data() + first;
    for (std::size_t j = 0; j < len; ++j) {
      const double c = k[j] ? row[j] - m[j] : 0.0;
      row[j] = c;
      out[j] = c * w[j];
    }
  }
}

}  // namespace matlas
