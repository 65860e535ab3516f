#include "eval/sparse_pca.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/error.h"

namespace matlas::eval {

SparsePca SparsePca::fit(const Eigen::MatrixXd& centred_gram) {
  const Eigen::Index m = centred_gram.rows();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(centred_gram);
  const Eigen::VectorXd lambda = eigen.eigenvalues();
  const double top = std::max(lambda.maxCoeff(), 1e-300);
  Eigen::Index k = 0;
  while (k < m && lambda(m - 1 - k) > 1e-10 * top) ++k;
  SparsePca pca;
  pca.coefficients.resize(m, k);
  pca.variance.resize(k);
  for (Eigen::Index c = 0; c < k; ++c) {
    const double l = lambda(m - 1 - c);
    pca.coefficients.col(c) = eigen.eigenvectors().col(m - 1 - c) / std::sqrt(l);
    pca.variance(c) = l / static_cast<double>(m);
  }
  return pca;
}

Eigen::MatrixXd SparsePca::components(const Eigen::MatrixXd& T) const {
  const Eigen::VectorXd mean = T.rowwise().mean();
  return (T.colwise() - mean) * coefficients;
}

Eigen::VectorXd SparsePca::solve(const Eigen::MatrixXd& U_S, const Eigen::VectorXd& r, double eta) const {
  Eigen::MatrixXd A = U_S.transpose() * U_S;
  A.diagonal() += eta * variance.cwiseInverse();
  return A.ldlt().solve(U_S.transpose() * r);
}

std::vector<int> condition_number_plan(const Eigen::MatrixXd& U, int rows_per, int count, int max_components) {
  if (rows_per < 1 || U.rows() % rows_per) throw Error("condition-number plan: rows do not split into candidates");
  const auto C = static_cast<int>(U.rows() / rows_per);
  const auto K = static_cast<int>(U.cols());
  count = std::min(count, C);
  std::vector<int> chosen;
  std::vector<bool> taken(static_cast<std::size_t>(C), false);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(K, K);  // U_S^T U_S over all K components
  for (int step = 0; step < count; ++step) {
    const int k = std::max(1, std::min({K, step + 1, max_components}));
    double best = std::numeric_limits<double>::infinity();
    int best_c = -1;
    for (int c = 0; c < C; ++c) {
      if (taken[static_cast<std::size_t>(c)]) continue;
      const auto rows = U.block(static_cast<Eigen::Index>(c) * rows_per, 0, rows_per, k);
      const Eigen::MatrixXd M = gram.topLeftCorner(k, k) + rows.transpose() * rows;
      const Eigen::VectorXd e = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues();
      // cond(U_S) = sqrt(max / min eigenvalue of U_S^T U_S); a singular one ranks by its rank
      // deficit first (more zero eigenvalues is worse), then by the largest eigenvalue.
      const double lo = e(0), hi = std::max(e(k - 1), 1e-300);
      const double score = lo > 1e-12 * hi ? std::sqrt(hi / lo) : 1e150 * (1 + static_cast<double>((e.array() <= 1e-12 * hi).count())) / hi;
      if (score < best) best = score, best_c = c;
    }
    if (best_c < 0) break;
    taken[static_cast<std::size_t>(best_c)] = true;
    const auto rows = U.middleRows(static_cast<Eigen::Index>(best_c) * rows_per, rows_per);
    gram.noalias() += rows.transpose() * rows;
    chosen.push_back(best_c);
  }
  return chosen;
}

}  // namespace matlas::eval
