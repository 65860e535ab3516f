#include "gp/posterior.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace matlas::gp {

GpPosterior::GpPosterior(Eigen::MatrixXd X, Kernel k) : X_(std::move(X)), kernel_(k) {
  validate(kernel_);
  if (X_.rows() == 0 || X_.cols() == 0) throw Error("GP posterior: no latent points (X is empty)");
  if (!X_.allFinite()) throw Error("GP posterior: latent points contain NaN or infinity");
  llt_.compute(covariance_matrix(X_, kernel_));
  if (!is_positive_definite(llt_))
    throw Error("GP posterior: the covariance matrix of the " + std::to_string(X_.rows()) +
                " latent points is not positive definite (duplicate points with nugget " +
                std::to_string(kernel_.nugget) + "?); use a nugget > 0");
}

Eigen::VectorXd GpPosterior::weights(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  return llt_.solve(cross_covariance(X_, x, kernel_));
}

Eigen::MatrixXd GpPosterior::weights_batch(const Eigen::MatrixXd& points) const {
  if (points.cols() != X_.cols())
    throw Error("GP posterior: points have dimension " + std::to_string(points.cols()) +
                " but the latent space has " + std::to_string(X_.cols()));
  return llt_.solve(cross_covariance_batch(X_, points, kernel_));
}

double GpPosterior::variance(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const Eigen::VectorXd kx = cross_covariance(X_, x, kernel_);
  // k^T K^-1 k = |L^-1 k|^2.
  return std::max(0.0, prior_variance(x) - llt_.matrixL().solve(kx).squaredNorm());
}

double GpPosterior::prior_variance(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  // c(x,x) = 1, plus the nugget when x is one of the data points (the white-noise part meets itself).
  const bool at_data = ((X_.rowwise() - x.transpose()).array() == 0.0).rowwise().all().any();
  return 1.0 + (at_data ? kernel_.nugget : 0.0);
}

GpPosterior::Batch GpPosterior::predict_batch(const Eigen::MatrixXd& points) const {
  if (points.cols() != X_.cols())
    throw Error("GP posterior: points have dimension " + std::to_string(points.cols()) +
                " but the latent space has " + std::to_string(X_.cols()));
  Batch b;
  // V = L^-1 k(x): variance = prior - |v|^2, weights = L^-T V = K^-1 k(x).
  Eigen::MatrixXd v = llt_.matrixL().solve(cross_covariance_batch(X_, points, kernel_));
  b.variance.resize(points.rows());
  for (Eigen::Index j = 0; j < points.rows(); ++j)
    b.variance[j] = std::max(0.0, prior_variance(points.row(j).transpose()) - v.col(j).squaredNorm());
  llt_.matrixU().solveInPlace(v);
  b.weights = std::move(v);
  return b;
}

double GpPosterior::log_det() const {
  return 2.0 * llt_.matrixLLT().diagonal().array().log().sum();
}

double GpPosterior::condition_estimate() const {
  const Eigen::Index n = X_.rows();
  // Deterministic, non-symmetric start vector (not orthogonal to the extreme eigenvectors in
  // practice).
  Eigen::VectorXd start(n);
  for (Eigen::Index i = 0; i < n; ++i) start[i] = 1.0 + 0.5 * std::sin(1.0 + 7.0 * static_cast<double>(i));
  start.normalize();
  const Eigen::MatrixXd K = covariance_matrix(X_, kernel_);
  constexpr int kSteps = 50;
  Eigen::VectorXd v = start;
  double lambda_max = 0;
  for (int s = 0; s < kSteps; ++s) {
    const Eigen::VectorXd w = K.selfadjointView<Eigen::Lower>() * v;
    lambda_max = v.dot(w);
    v = w.normalized();
  }
  v = start;
  double inv_lambda_min = 0;  // largest eigenvalue of K^-1
  for (int s = 0; s < kSteps; ++s) {
    const Eigen::VectorXd w = llt_.solve(v);
    inv_lambda_min = v.dot(w);
    v = w.normalized();
  }
  return lambda_max * inv_lambda_min;
}

}  // namespace matlas::gp
