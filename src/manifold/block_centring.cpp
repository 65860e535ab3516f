#include "manifold/block_centring.h"

#include <algorithm>

namespace matlas {

void kept_column_means(const BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
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

void subtract_column_means(BlockMatrix& values, const std::vector<std::uint8_t>& kept, std::size_t first,
                           std::size_t last, const double* mean) {
  const Eigen::Index n = values.rows();
  const std::size_t len = last - first;
  const double* m = mean + first;
  for (Eigen::Index i = 0; i < n; ++i) {
    double* row = values.row(i).data() + first;
    for (std::size_t j = 0; j < len; ++j) row[j] = kept[first + j] ? row[j] - m[j] : 0.0;
  }
}

}  // namespace matlas
