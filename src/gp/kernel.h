#pragma once
// The squared-exponential covariance function of the latent GP,
//   c(x, x') = exp(-|x - x'|^2 / l^2),
// plus a white-noise "nugget" delta on the diagonal of the covariance matrix (GpPosterior adds it
// to cross-covariances through a taper around each data point). Latent point sets are n x q
// matrices with one point per row.
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace matlas::gp {

/// Squared-exponential kernel with lengthscale l and nugget delta.
struct Kernel {
  double lengthscale = 1.0;  ///< l in c(x,x') = exp(-|x-x'|^2 / l^2)
  double nugget = 1e-4;      ///< delta added on the diagonal of the covariance matrix

  /// c(a, b) without the nugget.
  double operator()(const Eigen::Ref<const Eigen::VectorXd>& a,
                    const Eigen::Ref<const Eigen::VectorXd>& b) const;
};

/// Throws matlas::Error unless the lengthscale is finite and > 0 and the nugget finite and >= 0.
void validate(const Kernel& k);

/// Squared distances |x_i - x_j|^2 between the rows of X (n x q), written into D (n x n).
/// Computed from coordinate differences (not |a|^2 + |b|^2 - 2ab), so D is exactly symmetric with
/// an exactly zero diagonal and exact zeros for duplicate rows.
void squared_distances(const Eigen::MatrixXd& X, Eigen::MatrixXd& D);

/// K = exp(-D2 / l^2) + nugget I from squared distances D2 (n x n, symmetric), into K; exactly
/// symmetric (the upper triangle mirrored: a vectorised exp may round the array's tail differently).
void covariance_from_squared_distances(const Eigen::MatrixXd& D2, const Kernel& k, Eigen::MatrixXd& K);

/// n x n covariance of the rows of X (n x q), nugget on the diagonal. The nugget is added by index
/// (i == j), so duplicate rows give a matrix that is singular only up to the nugget.
Eigen::MatrixXd covariance_matrix(const Eigen::MatrixXd& X, const Kernel& k);

/// True when `llt` succeeded and no pivot is at rounding level: every L_ii^2 exceeds
/// n * epsilon * max_j L_jj^2. An exactly singular K (duplicate points with nugget 0) can pass
/// Eigen's own check (pivot > 0) with pivots of ~1e-16; this rejects it.
bool is_positive_definite(const Eigen::LLT<Eigen::MatrixXd>& llt);
/// The same test on the diagonal of a Cholesky factor computed elsewhere (LAPACK's dpotrf).
bool acceptable_cholesky_pivots(const Eigen::VectorXd& factor_diagonal);

}  // namespace matlas::gp
