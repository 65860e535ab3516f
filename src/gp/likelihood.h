#pragma once
// The GP-LVM log-likelihood of latent points X (n x q) for centred data Z (n x D'), with the
// signal variance s^2 profiled out in closed form (docs/GP.md has the derivation):
//   K_s = s^2 K,  s^2 = tr(K^-1 S) / (n D'),  S = (Z - mean)(Z - mean)^T,
//   L(X) = -D' log|K| - n D' log(tr(K^-1 S) / (n D')) - n D'.
// Only the n x n Gram S enters, so the data (millions of columns for MERL) is read once.
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "gp/kernel.h"

namespace matlas::gp {

/// Everything the likelihood needs besides X.
struct LikelihoodProblem {
  Eigen::MatrixXd gram;  ///< S = (Z - mean)(Z - mean)^T, n x n, symmetric PSD, double
  double columns = 1;    ///< D' = number of data columns (millions for MERL)
  Kernel kernel;
};

/// Profile log-likelihood of latent points X (n x q) with the signal variance s^2 fitted in closed
/// form: K_s = s^2 K, s^2 = tr(K^-1 S)/(n D'), giving
///   L(X) = -D' log|K| - n D' log(tr(K^-1 S) / (n D')) - n D'
/// (this is the paper's L = -D log|K| - tr(K^-1 Z Z^T) with the scale profiled out, so scaling
/// all data by any factor c changes L by -n D' log c and leaves the optimum unchanged).
/// Optionally fills the analytic gradient dL/dX (n x q). Uses Cholesky; throws matlas::Error if
/// K is not positive definite or the problem is malformed (see LikelihoodEvaluator).
double log_likelihood(const LikelihoodProblem& p, const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

/// Repeated evaluations of one problem (what the optimisers use). The constructor validates the
/// problem and factorises the normalised Gram S~ = S / sigma = R R^T (sigma = tr(S)/n, R from the
/// eigen-decomposition, eigenvalues below 1e-13 of the largest dropped; small negative ones from
/// rounding are clipped), so that an evaluation costs one Cholesky of K plus triangular solves
/// with the r = rank(S) columns of R, and allocates nothing after the first call.
///
/// It works with the normalised per-column value
///   l(X) = -log|K| - n log(tr(K^-1 S~) / n) - n  =  L(X)/D' + n log(sigma / D'),
/// which does not depend on D' or on the scale of the data; L = D' (l - n log(sigma / D')).
class LikelihoodEvaluator {
public:
  /// Throws matlas::Error if the Gram is not square, not finite, has zero trace (all data rows
  /// equal) or is clearly not PSD (an eigenvalue below -1e-6 of the largest), if columns is not
  /// finite and > 0, or if the kernel is invalid.
  explicit LikelihoodEvaluator(const LikelihoodProblem& p);

  int count() const { return static_cast<int>(R_.rows()); }  ///< n
  double columns() const { return columns_; }                ///< D'
  double scale() const { return sigma_; }                     ///< sigma = tr(S)/n
  int gram_rank() const { return static_cast<int>(R_.cols()); }
  const Kernel& kernel() const { return kernel_; }

  /// l(X) and optionally dl/dX. Throws matlas::Error if X has the wrong number of rows, is not
  /// finite, or K is not positive definite.
  double normalized(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

  /// L(X) and optionally dL/dX (= D' dl/dX), exactly as log_likelihood().
  double operator()(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

  /// Converts a normalised value l to L.
  double to_log_likelihood(double normalized_value) const;

private:
  Eigen::MatrixXd R_;  // n x r, S / sigma = R R^T
  double sigma_ = 1;
  double columns_ = 1;
  Kernel kernel_;
  // Workspaces, sized on first use.
  Eigen::MatrixXd K_, Y_, Kinv_, G_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace matlas::gp
