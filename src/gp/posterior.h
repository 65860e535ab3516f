#pragma once
// GpPosterior: the interpolation side of the latent GP. Given latent points X (n x q) and the
// kernel, a new latent point x gets the weights w(x) = K^-1 k(x), so that the posterior mean of
// any data attached to the points (an n x D matrix Y, e.g. centred BRDFs) is w(x)^T Y, and the
// posterior variance (in kernel units) tells how far x is from the data.
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "gp/kernel.h"

namespace matlas::gp {

/// Holds X, the kernel and the Cholesky factor of K = covariance_matrix(X, k).
class GpPosterior {
public:
  /// Factorises K. Throws matlas::Error if the kernel is invalid, X is empty or not finite, or K is
  /// not positive definite (e.g. duplicate latent points with nugget 0).
  GpPosterior(Eigen::MatrixXd X, Kernel k);

  int count() const { return static_cast<int>(X_.rows()); }  ///< n, the number of latent points
  int dim() const { return static_cast<int>(X_.cols()); }    ///< q, the latent dimension
  const Eigen::MatrixXd& latent() const { return X_; }       ///< the n x q latent points
  const Kernel& kernel() const { return kernel_; }

  /// w(x) = K^-1 k(x) (length n). At a data point x_i this is e_i (to rounding), so the GP
  /// reproduces the data exactly there. The nugget enters k(x) continuously: k_i(x) =
  /// c(x, x_i) + delta phi_i(|x - x_i|), phi_i a C1 bump of radius min(0.1 l, half the distance
  /// from x_i to its nearest other point), 1 at x_i. (A nugget added only when x equals x_i
  /// exactly makes w jump by delta K^-1 e_i at every data point, which is O(1) where K is
  /// ill-conditioned.) Throws matlas::Error if x has the wrong dimension.
  Eigen::VectorXd weights(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  /// The weights of many points at once: points is m x q, the result n x m (column j = weights of
  /// points.row(j)). Equal to calling weights() per point, up to rounding.
  Eigen::MatrixXd weights_batch(const Eigen::MatrixXd& points) const;

  /// Posterior variance c(x,x) + nugget*[x in X] - k^T K^-1 k, clamped at 0: ~0 at the data
  /// points, -> 1 far away from them (kernel units: multiply by the fitted signal variance s^2 for
  /// data units).
  double variance(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// Weights (n x m) and variances (length m) of many points (m x q) at once: k(x) in blocks of
  /// points, each multiplied by K^-1 (from the Cholesky factor) in one product, the blocks in
  /// parallel. Equal to weights() and variance() per point up to rounding.
  struct Batch {
    Eigen::MatrixXd weights;
    Eigen::VectorXd variance;
    /// predict_grid: the rank of the lines' kernel factors; 0 where computed point by point.
    Eigen::Index rank = 0;
  };
  Batch predict_batch(const Eigen::MatrixXd& points) const;

  /// A regular grid on a plane of the latent space: cell (r, c), numbered r * u.size() + c, is
  /// origin + u[c] axis_u + v[r] axis_v.
  struct PlaneGrid {
    Eigen::VectorXd origin, axis_u, axis_v;  ///< q values each; the axes orthonormal
    Eigen::VectorXd u, v;                    ///< the columns' and the rows' plane coordinates
  };
  /// predict_batch of the grid's cells (column r * u.size() + c for cell (r, c)), through the
  /// kernel's separability on the plane: along a line of cells (a row, or a column) the kernel
  /// values are diag(d) F, one n x m matrix F of Gaussians in the line's coordinate for every
  /// line, scaled per line. F's numerical rank R is far below m (Gaussians of width l over a
  /// few lengthscales: 27 of 128 at n = 1000), so K^-1 k over a line is (K^-1 diag(d) F V)
  /// V^T with F's first R right singular vectors V: one product of K^-1 by n x (lines R)
  /// instead of n x cells. The lines run along the axis whose R is smaller; the nugget's taper
  /// (a few cells at the data points) and the variances use the exact kernel values. Equal to
  /// predict_batch up to F's truncation (singular values under 1e-15 of the largest, times
  /// |K^-1|). Axes that are not orthonormal, or a rank that saves little, go through
  /// predict_batch. Throws matlas::Error if the plane does not have q coordinates or a value is
  /// not finite.
  Batch predict_grid(const PlaneGrid& grid) const;

  /// log|K| (from the Cholesky factor).
  double log_det() const;

  /// Estimate of the 2-norm condition number of K = lambda_max / lambda_min, by a few steps of
  /// power and inverse-power iteration (deterministic start). A diagnostic, not a bound: it is at
  /// most the true condition number and usually within a few percent of it.
  double condition_estimate() const;

  /// The Cholesky factorisation of K.
  const Eigen::LLT<Eigen::MatrixXd>& cholesky() const { return llt_; }

  /// Radius of the nugget's taper around each data point (see weights()).
  const Eigen::VectorXd& taper_radius() const { return taper_radius_; }

private:
  /// K^-1, both triangles (from the Cholesky factor).
  Eigen::MatrixXd inverse() const;
  /// k(x) with the tapered nugget; `noise` (optional) receives nugget * sum_i phi_i(x)^2, the
  /// tapered white noise meeting itself (part of c(x, x)).
  Eigen::VectorXd cross(const Eigen::Ref<const Eigen::VectorXd>& x, double* noise = nullptr) const;

  Eigen::MatrixXd X_;
  Eigen::VectorXd taper_radius_;
  Kernel kernel_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace matlas::gp
