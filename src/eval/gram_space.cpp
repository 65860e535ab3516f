#include "eval/gram_space.h"

#include "core/combination.h"
#include "core/error.h"

namespace matlas::eval {

std::vector<int> indices_without(int n, int left_out) {
  std::vector<int> idx;
  idx.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    if (i != left_out) idx.push_back(i);
  return idx;
}

Eigen::MatrixXd centred_subset_gram(const Eigen::MatrixXd& gram, std::span<const int> subset) {
  const auto m = static_cast<Eigen::Index>(subset.size());
  Eigen::MatrixXd g(m, m);
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = 0; b < m; ++b) g(a, b) = gram(subset[a], subset[b]);
  const Eigen::VectorXd row_mean = g.rowwise().mean();
  const double total = row_mean.mean();
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = 0; b < m; ++b) g(a, b) += total - row_mean(a) - row_mean(b);
  return 0.5 * (g + g.transpose());
}

Eigen::VectorXd centred_cross_products(const Eigen::MatrixXd& gram, std::span<const int> subset,
                                       int h) {
  const auto m = static_cast<Eigen::Index>(subset.size());
  Eigen::VectorXd row_mean = Eigen::VectorXd::Zero(m);
  double cross_mean = 0;  // mean_j G(j, h)
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) row_mean(a) += gram(subset[a], subset[b]);
    row_mean(a) /= static_cast<double>(m);
    cross_mean += gram(subset[a], h);
  }
  cross_mean /= static_cast<double>(m);
  const double total = row_mean.mean();
  Eigen::VectorXd g(m);
  for (Eigen::Index a = 0; a < m; ++a)
    g(a) = gram(subset[a], h) - cross_mean - row_mean(a) + total;
  return g;
}

Eigen::VectorXd raw_from_centred(const Eigen::VectorXd& a, std::span<const int> subset, int n) {
  if (a.size() != static_cast<Eigen::Index>(subset.size()))
    throw Error("raw_from_centred: coefficient count does not match the subset");
  const Eigen::VectorXd g = Combination(a).affine();
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
  for (std::size_t k = 0; k < subset.size(); ++k) c(subset[k]) = g(static_cast<Eigen::Index>(k));
  return c;
}

double residual_squared(const Eigen::MatrixXd& gram, const Eigen::VectorXd& c, int h) {
  Eigen::VectorXd d = -c;
  d(h) += 1.0;
  return std::max(0.0, d.dot(gram * d));
}

Eigen::MatrixXd squared_distances_from_gram(const Eigen::MatrixXd& gram) {
  const Eigen::Index n = gram.rows();
  Eigen::MatrixXd d(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      d(i, j) = std::max(0.0, gram(i, i) + gram(j, j) - 2.0 * gram(i, j));
  return d;
}

}  // namespace matlas::eval
