#pragma once
// The sparse GP-LVM objective: the likelihood of likelihood.h with two approximations that make an
// evaluation O(n m^2 + n m r) instead of O(n^3) (docs/GP.md, "Sparse latent optimisation"):
//   the data term: S ~= Y Y^T + (e / n) I, Y = n x r (the r leading eigenvectors of S scaled by
//     the square roots of their eigenvalues), e = tr(S) - tr(Y Y^T) spread evenly (isotropic residual);
//   the covariance: K ~= K~ = Q + Lambda, the FITC approximation (Snelson & Ghahramani 2006) with m
//     inducing points Z (m x q): Q = C_nm C_mm^-1 C_mn, Lambda = diag(1 + delta - Q_ii), exact on
//     the diagonal, so K~ -> K as the inducing points cover the latent points (with m = n and Z = X,
//     K~ = K up to the jitter of C_mm).
// log|K~| by the matrix determinant lemma and K~^-1 by Woodbury through one m x m Cholesky. The
// inducing points are optimised together with the latent points. The repulsive prior is evaluated
// on the pairs within its cutoff only (a sweep over the points sorted by their first coordinate),
// which gives the value the dense evaluation gives: it too drops pairs beyond the cutoff.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "gp/kernel.h"
#include "gp/likelihood.h"

namespace matlas::gp {

/// A Gram matrix S ~= Y Y^T + (residual / n) I.
struct LowRankGram {
  Eigen::MatrixXd factor;  ///< Y, n x r, columns in decreasing order of their norms
  double residual = 0;     ///< tr(S) - tr(Y Y^T) >= 0
};

/// The rank-r truncation of a symmetric PSD Gram S (n x n): exact eigen-decomposition for n <= 400
/// or r >= n / 4, else randomised subspace iteration (Halko et al. 2011: 4 power iterations with r + 16
/// columns, then the small eigenproblem; O(n^2 r)). Deterministic for a given seed. Throws
/// matlas::Error for a non-square or non-finite S or r < 1. r is capped at n.
LowRankGram low_rank_gram(const Eigen::MatrixXd& S, int rank, std::uint64_t seed = 1);

/// Everything the sparse objective needs besides the latent and inducing points.
struct SparseProblem {
  LowRankGram data;     ///< S ~= Y Y^T + residual/n I (any scale: it is normalised like S)
  double columns = 1;   ///< D'
  Kernel kernel;
  LatentPrior prior{};
  double jitter = 1e-8;  ///< added to the diagonal of C_mm (the inducing points' covariance)
};

/// Repeated evaluations of the sparse objective, in the normalised units of LikelihoodEvaluator:
///   l(X, Z) = -beta log|K~| - n log(t / n) - n + priors,  t = tr(K~^-1 S~),
/// S~ = S / sigma, sigma = tr(S) / n (the factor's trace plus the residual). With m = n inducing
/// points at X, r = n and no jitter this is LikelihoodEvaluator::normalized(X).
class SparseLikelihoodEvaluator {
public:
  /// Throws matlas::Error for an empty or non-finite factor, a negative residual, zero trace,
  /// columns not finite and > 0, a negative jitter, or invalid kernel or priors.
  explicit SparseLikelihoodEvaluator(const SparseProblem& p);

  int count() const { return static_cast<int>(Y_.rows()); }  ///< n
  int rank() const { return static_cast<int>(Y_.cols()); }   ///< r
  double scale() const { return sigma_; }                      ///< sigma = tr(S) / n
  double columns() const { return columns_; }

  /// l(X, Z) and optionally its gradients with respect to X (n x q) and Z (m x q) (either may
  /// be null). Throws matlas::Error if the shapes disagree, a point is not finite, or C_mm + jitter
  /// is not positive definite.
  double normalized(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z, Eigen::MatrixXd* grad_X = nullptr,
                    Eigen::MatrixXd* grad_Z = nullptr);

  /// Converts a normalised value to L (as LikelihoodEvaluator::to_log_likelihood).
  double to_log_likelihood(double normalized_value) const;

  /// The blocks of the exact local covariance (PITC): a partition of 0..n-1. K~ = Q +
  /// blockdiag_b(C_bb - Q_bb) + delta I. Singletons (the default) give FITC; one block of all
  /// items gives the exact K whatever the inducing points. Throws matlas::Error unless a partition.
  void set_blocks(std::vector<std::vector<Eigen::Index>> blocks);
  const std::vector<std::vector<Eigen::Index>>& blocks() const { return blocks_; }

private:
  /// normalized()'s first half: C_nm, C_mm, V, the blocks' Lambda_b^-1 factors, A and U for the
  /// points X and inducing points Z; returns log|K~|.
  double factorize(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z);
  /// factorize()'s blocks: Lambda_b^-1's factors and A = I + V Lambda^-1 V^T from V; log|Lambda|.
  /// The diagonal variant is the one for singleton blocks (FITC), as vectors instead of n blocks.
  double factorize_blocks(const Eigen::MatrixXd& X);
  double factorize_diagonal();
  /// normalized()'s second half: the gradients of the likelihood part (t = tr(K~^-1 S)) added to
  /// grad_X (which holds the repulsion's) and written to grad_Z, from the state factorize() left.
  void add_gradient(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z, double t, Eigen::MatrixXd* grad_X,
                    Eigen::MatrixXd* grad_Z);
  /// add_gradient()'s blocks of G (c = n/t, UtU = U^T U when eps > 0): each subtracts G_bb P_b^T
  /// from W and adds tr(G_bb dC_bb) to grad_X; the diagonal variant for singleton blocks.
  void add_block_terms(const Eigen::MatrixXd& X, double c, const Eigen::MatrixXd& UtU, Eigen::MatrixXd* grad_X);
  void add_diagonal_terms(double c, const Eigen::MatrixXd& UtU);
  void apply_inverse(const Eigen::MatrixXd& M, Eigen::MatrixXd& out) const;        // out = K~^-1 M
  void apply_block_inverse(const Eigen::MatrixXd& M, Eigen::MatrixXd& out) const;  // out = Lambda^-1 M

  Eigen::MatrixXd Y_;  // S~ factor, n x r
  double eps_ = 0;     // S~ residual per diagonal entry
  double sigma_ = 1, columns_ = 1;
  Kernel kernel_;
  double beta_ = 1, repulsion_ = 0, radius_ = 0.1, precision_ = 0, jitter_ = 1e-8;
  // Workspaces: C_nm, L_m^-1, V = L_m^-1 C_mn, Lambda^-1, U (K~^-1 = Lambda^-1 - U U^T), B = K~^-1 Y.
  Eigen::MatrixXd Cnm_, Cmm_, Lminv_, V_, A_, U_, B_, Pt_, H1_, H2_, W_;
  std::vector<std::vector<Eigen::Index>> blocks_;
  std::vector<Eigen::MatrixXd> block_inv_, block_cov_;  // L_b^-1 (lower) and C_bb per block
  bool diagonal_ = true;        // every block a singleton (FITC): Lambda is diagonal
  Eigen::VectorXd lambda_inv_;  // then Lambda^-1's diagonal (block_inv_ and block_cov_ unused)
};

/// m points of X chosen by farthest-point sampling (the first is the point nearest the centroid),
/// so that the inducing points cover the latent points; m is capped at n. Deterministic.
Eigen::MatrixXd farthest_point_subset(const Eigen::MatrixXd& X, int m);
/// The rows of X that farthest_point_subset picks, in its order.
std::vector<Eigen::Index> farthest_point_indices(const Eigen::MatrixXd& X, int m);

}  // namespace matlas::gp
