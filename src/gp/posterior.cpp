#include "gp/posterior.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/vector_math.h"

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
  // Taper radii: a tenth of a lengthscale, at most half the distance to the nearest other point
  // (so no two tapers overlap and w(x_i) = e_i exactly); 0 for exact duplicates.
  const Eigen::Index n = X_.rows();
  taper_radius_ = Eigen::VectorXd::Constant(n, 0.1 * kernel_.lengthscale);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != i) taper_radius_[i] = std::min(taper_radius_[i], 0.5 * (X_.row(i) - X_.row(j)).norm());
}

double GpPosterior::taper(Eigen::Index i, double distance) const {
  const double r = taper_radius_[i];
  if (distance == 0.0) return 1.0;
  if (!(distance < r)) return 0.0;
  const double t = distance / r;
  return (1.0 - t * t) * (1.0 - t * t);
}

Eigen::VectorXd GpPosterior::cross(const Eigen::Ref<const Eigen::VectorXd>& x, double* noise) const {
  if (x.size() != X_.cols())
    throw Error("GP posterior: point has dimension " + std::to_string(x.size()) + " but the latent space has " +
                std::to_string(X_.cols()));
  const Eigen::Index n = X_.rows();
  Eigen::VectorXd d2 = Eigen::VectorXd::Zero(n);
  for (Eigen::Index d = 0; d < X_.cols(); ++d) d2.array() += (X_.col(d).array() - x[d]).square();
  Eigen::VectorXd kx = d2 * (-1.0 / (kernel_.lengthscale * kernel_.lengthscale));
  exp_in_place(kx.data(), static_cast<std::size_t>(n));
  double s = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(d2[i] < taper_radius_[i] * taper_radius_[i]) && d2[i] != 0.0) continue;
    const double phi = taper(i, std::sqrt(d2[i]));
    kx[i] += kernel_.nugget * phi;
    s += phi * phi;
  }
  if (noise) *noise = kernel_.nugget * s;
  return kx;
}

Eigen::VectorXd GpPosterior::weights(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  return llt_.solve(cross(x));
}

Eigen::MatrixXd GpPosterior::weights_batch(const Eigen::MatrixXd& points) const {
  if (points.cols() != X_.cols())
    throw Error("GP posterior: points have dimension " + std::to_string(points.cols()) +
                " but the latent space has " + std::to_string(X_.cols()));
  Eigen::MatrixXd k(X_.rows(), points.rows());
  for (Eigen::Index j = 0; j < points.rows(); ++j) k.col(j) = cross(points.row(j).transpose());
  return llt_.solve(k);
}

double GpPosterior::variance(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  double noise = 0;
  const Eigen::VectorXd kx = cross(x, &noise);
  // k^T K^-1 k = |L^-1 k|^2; c(x, x) = 1 plus the tapered nugget meeting itself.
  return std::max(0.0, 1.0 + noise - llt_.matrixL().solve(kx).squaredNorm());
}

GpPosterior::Batch GpPosterior::predict_batch(const Eigen::MatrixXd& points) const {
  if (points.cols() != X_.cols())
    throw Error("GP posterior: points have dimension " + std::to_string(points.cols()) +
                " but the latent space has " + std::to_string(X_.cols()));
  Batch b;
  // V = L^-1 k(x): variance = prior - |v|^2, weights = L^-T V = K^-1 k(x).
  Eigen::MatrixXd v(X_.rows(), points.rows());
  Eigen::VectorXd noise(points.rows());
  for (Eigen::Index j = 0; j < points.rows(); ++j) v.col(j) = cross(points.row(j).transpose(), &noise[j]);
  llt_.matrixL().solveInPlace(v);
  b.variance.resize(points.rows());
  for (Eigen::Index j = 0; j < points.rows(); ++j) b.variance[j] = std::max(0.0, 1.0 + noise[j] - v.col(j).squaredNorm());
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
