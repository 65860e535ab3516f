#include "manifold/block_centring.h"

#include <algorithm>

#include "core/simd_clones.h"

namespace matlas {

MATLAS_SIMD_CLONES void column_means_from_sums(const double* sums, std::size_t stride, std::size_t groups,
                                               const std::uint8_t* kept, std::size_t first, std::size_t last,
                                               std::size_t n, double* mean) {
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

MATLAS_SIMD_CLONES void centre_kept(const BlockMatrix& values, std::span<const KeptRun> runs, const double* mean,
                                    double* centred, const float* weight, float* weighted, std::size_t ld) {
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double* row = values.row(i).data();
    const auto offset = static_cast<std::size_t>(i) * ld;
    for (const KeptRun& run : runs) {
      const double* __restrict in = row + run.first;
      const double* __restrict m = mean + run.first;
      double* __restrict c = centred + offset + run.out;
      if (weighted) {
        const float* __restrict w = weight + run.first;
        float* __restrict out = weighted + offset + run.out;
        for (std::size_t j = 0; j < run.count; ++j) {
          const double x = in[j] - m[j];
          c[j] = x;
          out[j] = static_cast<float>(x * w[j]);
        }
      } else {
        for (std::size_t j = 0; j < run.count; ++j) c[j] = in[j] - m[j];
      }
    }
  }
}

MATLAS_SIMD_CLONES void subtract_own_means(float* a, std::size_t rows, std::size_t ld, std::size_t first,
                                           std::size_t last) {
  constexpr std::size_t kChunk = 512;
  for (std::size_t j0 = first; j0 < last; j0 += kChunk) {
    const std::size_t len = std::min(kChunk, last - j0);
    double sum[kChunk] = {};
    for (std::size_t i = 0; i < rows; ++i) {
      const float* __restrict row = a + i * ld + j0;
      for (std::size_t j = 0; j < len; ++j) sum[j] += row[j];
    }
    float mean[kChunk];
    const double inv = 1.0 / static_cast<double>(rows);
    for (std::size_t j = 0; j < len; ++j) mean[j] = static_cast<float>(sum[j] * inv);
    for (std::size_t i = 0; i < rows; ++i) {
      float* __restrict row = a + i * ld + j0;
      for (std::size_t j = 0; j < len; ++j) row[j] -= mean[j];
    }
  }
}

}  // namespace matlas
