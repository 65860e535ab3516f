#pragma once
// The GP-LVM log-likelihood of latent points X (n x q) for centred data Z (n x D'), with the
// signal variance s^2 profiled out in closed form (docs/GP.md has the derivation):
//   K_s = s^2 K,  s^2 = tr(K^-1 S) / (n D'),  S = (Z - mean)(Z - mean)^T,
//   L(X) = -D' log|K| - n D' log(tr(K^-1 S) / (n D')) - n D'.
// Only the n x n Gram S enters, so the data (millions of columns for MERL) is read once.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "gp/kernel.h"

namespace matlas::gp {

/// Priors on the latent points, added to the likelihood (MAP placement; docs/GP.md, "Spreading
/// the layout"). Each term is scaled by D' like the likelihood, so its strength does not depend on
/// the number of data columns. The defaults are all off (the paper's likelihood); spread() is
/// what `matlas build` uses.
/// The repulsion barrier is log(1 - e^{-u} + floor): finite (-27.6 lambda) for coincident points,
/// so a start with duplicate coordinates (a PCA start of a tiny database) can still be evaluated.
inline constexpr double kRepulsionFloor = 1e-12;

struct LatentPrior {
  /// Hard-core repulsion lambda sum_{i<j} log(1 - exp(-|x_i - x_j|^2 / rho^2) + 1e-12) (lambda =
  /// repulsion, rho = radius in lengthscale units): a barrier that keeps any two points about rho
  /// apart and vanishes beyond a few rho, so distinct materials stay distinct on the map where the
  /// likelihood alone would merge them (it rewards merging similar materials by -log|K|).
  double repulsion = 0.0;
  double radius = 0.1;
  /// Gaussian prior -(gamma / 2) sum_i |x_i|^2 (gamma = precision): keeps the extent bounded
  /// (a material unrelated to all others would otherwise drift off at no cost).
  double precision = 0.0;
  /// beta: weight of the complexity term -D' log|K| (1 = the likelihood; beta < 1 is a
  /// determinantal repulsive prior (1 - beta) D' log|K| with the GP's own kernel).
  double complexity_weight = 1.0;

  /// The defaults of `matlas build`, chosen on the 83 realistic materials (docs/EVALUATION.md).
  static LatentPrior spread() { return {1.0, 0.1, 0.1, 1.0}; }
  bool is_off() const { return repulsion == 0 && precision == 0 && complexity_weight == 1; }
};

/// The normalised Gram S~ = S / sigma = R R^T (sigma = tr(S)/n, R from the eigen-decomposition,
/// eigenvalues below 1e-13 of the largest dropped, small negative ones from rounding clipped;
/// R's columns in ascending order of eigenvalue): what every evaluation of one Gram shares.
struct GramFactor {
  double sigma = 1;
  Eigen::MatrixXd R;  ///< n x r
};

/// Validates S and factorises it (an O(n^3) eigen-decomposition: 0.2 s for n = 1000, about five
/// evaluations; docs/GP.md). Throws matlas::Error if S is not square, not finite, has zero trace
/// (all data rows equal) or is clearly not PSD (an eigenvalue below -1e-6 of the largest).
std::shared_ptr<const GramFactor> gram_factor(const Eigen::MatrixXd& gram);

/// Everything the likelihood needs besides X.
struct LikelihoodProblem {
  Eigen::MatrixXd gram;  ///< S = (Z - mean)(Z - mean)^T, n x n, symmetric PSD, double
  double columns = 1;    ///< D' = number of data columns (millions for MERL)
  Kernel kernel;
  /// Priors on the latent points (all off: the paper's plain likelihood).
  LatentPrior prior{};
  /// gram_factor(gram), when computed once for the many evaluators of a placement (the PCA start,
  /// the scale searches, the optimiser); otherwise each evaluator computes it. It must be the
  /// factor of this gram: a problem derived with another Gram (a subset) leaves it empty.
  std::shared_ptr<const GramFactor> factor;
};

/// p with its factor computed when it has none (a copy; p itself when it has one).
LikelihoodProblem with_factor(const LikelihoodProblem& p);

/// Profile log-likelihood of latent points X (n x q) with the signal variance s^2 fitted in closed
/// form: K_s = s^2 K, s^2 = tr(K^-1 S)/(n D'), giving
///   L(X) = -D' log|K| - n D' log(tr(K^-1 S) / (n D')) - n D'
/// (this is the paper's L = -D log|K| - tr(K^-1 Z Z^T) with the scale profiled out, so scaling
/// all data by any factor c changes L by -n D' log c and leaves the optimum unchanged).
/// Optionally fills the analytic gradient dL/dX (n x q). Uses Cholesky; throws matlas::Error if
/// K is not positive definite or the problem is malformed (see LikelihoodEvaluator).
double log_likelihood(const LikelihoodProblem& p, const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

/// Repeated evaluations of one problem (what the optimisers use). The constructor validates the
/// problem and takes its factor S / sigma = R R^T (GramFactor, computed here unless the problem
/// carries it), so that an evaluation costs one Cholesky of K plus products with the r = rank(S)
/// columns of R, and allocates nothing after the first call.
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

  int count() const { return static_cast<int>(factor_->R.rows()); }  ///< n
  double columns() const { return columns_; }                         ///< D'
  double scale() const { return factor_->sigma; }                     ///< sigma = tr(S)/n
  /// S / sigma = R R^T.
  const GramFactor& factor() const { return *factor_; }
  const Kernel& kernel() const { return kernel_; }
  double complexity_weight() const { return beta_; }

  /// l(X) and optionally dl/dX. Throws matlas::Error if X has the wrong number of rows, is not
  /// finite, or K is not positive definite.
  double normalized(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

  /// L(X) and optionally dL/dX (= D' dl/dX), exactly as log_likelihood().
  double operator()(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

  /// Converts a normalised value l to L.
  double to_log_likelihood(double normalized_value) const;

private:
  std::shared_ptr<const GramFactor> factor_;
  double columns_ = 1;
  Kernel kernel_;
  double beta_ = 1;
  double repulsion_ = 0, radius_ = 0.1, precision_ = 0;
  // Workspaces, sized on first use.
  Eigen::MatrixXd K_, L_, W_, B_, Kinv_, G_;  // L_: K's Cholesky factor in its lower triangle; W_: L^-1; B_ = K^-1 R
  Eigen::MatrixXd D2_, E_, Logs_, F_;     // squared distances; the repulsion's expm1, log and forces
  std::vector<double> sums_;               // the repulsion's sum per block of columns
};

}  // namespace matlas::gp
