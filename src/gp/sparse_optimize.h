#pragma once
// Latent placement with the sparse objective (sparse_likelihood.h): the PCA start and its scale
// search, then L-BFGS over the latent and the inducing points together. For databases past a few
// thousand materials, where the exact likelihood's O(n^3) evaluation is too slow
// (docs/GP.md, "Sparse latent optimisation").
#include <Eigen/Core>
#include <vector>

#include "core/progress.h"
#include "gp/optimize.h"
#include "gp/sparse_likelihood.h"

namespace matlas::gp {

/// What `matlas build --sparse-inducing M` sets: M inducing points (0: the exact likelihood) and
/// the rank of the data term.
struct SparseOptions {
  int inducing = 0;  ///< m; 0 = exact optimisation (the default)
  int rank = 64;     ///< r of S ~= Y Y^T + residual (the rest of the trace spread evenly)
  /// false (the default): the inducing points are m of the latent points (chosen by
  /// farthest_point_indices at the start) and move with them; true: free variables optimised
  /// alongside (Titsias & Lawrence's choice; with FITC it lets the layout drift from the exact
  /// likelihood's, docs/GP.md).
  bool free_inducing = false;
  /// The largest block of exact local covariance (PITC): the points nearest each inducing point at
  /// the start, split into runs of at most `block` points along the first coordinate. 1 = FITC.
  int block = 1;
  /// Coarse-to-fine (gp/coarse_placement.h): when 0 < coarse < n, `coarse` items chosen at random
  /// are placed first (every start runs on them), the others interpolated from their nearest
  /// placed items in the data, the layout scaled to the whole problem's best, and refined from
  /// there. 0: all at once. -1 (the default): automatic_coarse(n).
  int coarse = -1;
  bool enabled() const { return inducing > 0; }
};

/// The coarse subset's size SparseOptions::coarse = -1 stands for: n / 10 from n = 2000 on (where
/// it placed generated problems better in less time, docs/GP.md), else 0 (all at once).
int automatic_coarse(Eigen::Index n);

/// The sparse problem of an exact one: the rank-r truncation of its Gram (low_rank_gram), its
/// columns, kernel and priors.
SparseProblem sparse_problem(const LikelihoodProblem& p, int rank);

/// A partition of the rows of X into blocks: each point goes to its nearest row of Z (Voronoi
/// cells), and a cell of more than max_block points is split into runs of at most max_block along
/// the first coordinate. Throws matlas::Error for max_block < 1.
std::vector<std::vector<Eigen::Index>> local_blocks(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z, int max_block);

/// PCA initialisation as pca_initialization: the q leading columns of the data factor (signs fixed
/// so the largest-magnitude entry is positive), scaled by the factor maximising the sparse
/// objective with `inducing` inducing points chosen among them (farthest_point_subset) and blocks
/// of at most `block` points (local_blocks).
Eigen::MatrixXd sparse_pca_initialization(const SparseProblem& p, int q, int inducing, int block = 1);

/// Maximises the sparse objective over X (and the inducing points Z when s.free_inducing) from X0,
/// the inducing points being the rows farthest_point_indices(X0, s.inducing) of X and the blocks
/// those of local_blocks(X0, inducing points, s.block), with L-BFGS (LBFGSpp, the same stopping rules as
/// optimize_latent's L-BFGS; Hooke-Jeeves is refused). Starts after the first are X0 scaled about
/// its centroid as optimize_latent's, run one after the other. The result's value and history are
/// the sparse objective in log-likelihood units (to_log_likelihood); *inducing_out receives the
/// winning Z. With s.coarse in (0, n) the starts run on the coarse subset and the refinement of
/// the whole layout follows (iterations, evaluations and seconds are the two stages' sums; the
/// history is the refinement's). Throws matlas::Error for a malformed problem or options.
OptimizeResult optimize_sparse_latent(const SparseProblem& p, const Eigen::MatrixXd& X0, const SparseOptions& s,
                                      const OptimizeOptions& o, ProgressSink& sink,
                                      Eigen::MatrixXd* inducing_out = nullptr);

}  // namespace matlas::gp
