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

}  // namespace matlas
