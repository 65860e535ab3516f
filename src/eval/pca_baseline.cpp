#include "eval/pca_baseline.h"

#include <Eigen/Eigenvalues>

#include "core/error.h"
#include "eval/gram_space.h"

namespace matlas::eval {

Eigen::VectorXd pca_reconstruction(const Eigen::MatrixXd& gram, std::span<const int> subset, int h,
                                   int components) {
  if (components < 0) throw Error("PCA baseline: negative number of components");
  const Eigen::MatrixXd s = centred_subset_gram(gram, subset);
  const Eigen::VectorXd g = centred_cross_products(gram, subset, h);
  // S = V L V^T; u_k = sum_i V_ik (z_i - m) / sqrt(l_k); <z_h - m, u_k> = (V^T g)_k / sqrt(l_k);
  // r - m = sum_k (V^T g)_k / l_k * sum_i V_ik (z_i - m)  =>  a = V_q L_q^-1 V_q^T g.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  const Eigen::Index m = s.rows();
  const double largest = eig.eigenvalues().size() ? eig.eigenvalues()(m - 1) : 0.0;
  Eigen::VectorXd a = Eigen::VectorXd::Zero(m);
  for (int k = 0; k < components && k < m; ++k) {
    const Eigen::Index col = m - 1 - k;  // eigenvalues are ascending
    const double lambda = eig.eigenvalues()(col);
    if (!(lambda > 1e-12 * largest) || lambda <= 0) break;
    const Eigen::VectorXd v = eig.eigenvectors().col(col);
    a += v * (v.dot(g) / lambda);
  }
  return raw_from_centred(a, subset, static_cast<int>(gram.rows()));
}

}  // namespace matlas::eval
