#include "manifold/block_centring.h"

namespace matlas {

void centre_kept_columns(BlockMatrix& values, const std::vector<std::uint8_t>& kept,
                         Eigen::RowVectorXd& mean) {
  const Eigen::Index n = values.rows(), k = values.cols();
  mean.setZero(k);
  for (Eigen::Index i = 0; i < n; ++i) mean += values.row(i);
  mean /= static_cast<double>(n);
  Eigen::RowVectorXd mask(k);
  for (Eigen::Index j = 0; j < k; ++j) mask[j] = kept[static_cast<std::size_t>(j)] ? 1.0 : 0.0;
  mean.array() *= mask.array();
  for (Eigen::Index i = 0; i < n; ++i)
    values.row(i).array() = (values.row(i).array() - mean.array()) * mask.array();
}

}  // namespace matlas
