#pragma once
// Maximising the GP-LVM likelihood over the latent points: L-BFGS on the analytic gradient (the
// default), or the derivative-free Hooke-Jeeves pattern search used in the paper.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "core/progress.h"
#include "gp/likelihood.h"

namespace matlas::gp {

enum class Optimizer { lbfgs, hooke_jeeves };

/// Limits and stopping rules. Both methods work on the normalised value l = L/D' + const
/// (LikelihoodEvaluator), which is O(n) whatever D' and the data scale are.
struct OptimizeOptions {
  Optimizer method = Optimizer::lbfgs;
  /// L-BFGS: iterations (one line search each); Hooke-Jeeves: exploratory sweeps over all n*q
  /// coordinates. -1: automatic (`matlas build`'s default, resolved()): 5000, and from
  /// kLargePlacement items on 10^11 / n^3, at least 100 (800 at n = 500, 100 at n = 1000): one
  /// iteration costs O(n^3), so the refinement takes about the same time from 500 to 1000 items
  /// (6 s here) instead of growing with n^3 past the pass over the data (docs/BENCHMARKS.md,
  /// "n = 1000 on one machine").
  int max_iterations = 5000;
  /// L-BFGS: stops when l improved by at most tolerance * max(1, |l|) over the last 3 iterations,
  /// or when |grad l| <= tolerance * max(1, |l(X0)|), or when the line search cannot improve l
  /// twice in a row (after a restart of the curvature memory).
  /// Hooke-Jeeves: stops when the step h falls below sqrt(tolerance) * h0 (for a smooth maximum
  /// the value is then within ~tolerance of it, relative); h0 = 0.1 * RMS radius of X0.
  double tolerance = 1e-7;
  double time_limit_seconds = 0;  ///< 0 = none; checked at every evaluation
  /// Stop as soon as an evaluated L reaches this value (benchmarks: time to reach a given L).
  double target_value = std::numeric_limits<double>::infinity();
  /// Number of starting points: X0 itself, then X0 scaled about its centroid by 2^(-1/2), 2^(1/2),
  /// 2^-1, 2^1, 2^(-3/2), ... Each start is optimised on its own and the best result is returned.
  /// The likelihood is multimodal (mostly for q <= 2) and the spread of the start decides the
  /// basin; with L-BFGS a few starts cost little. The limits (iterations per start, time and
  /// target overall) apply as documented above.
  int starts = 1;
  /// Coarse-to-fine (gp/coarse_placement.h, docs/GP.md): when 0 < coarse < n, `coarse` items
  /// chosen at random are placed first (from their rows of X0; every start runs on them, with at
  /// least kCoarseIterations iterations: one costs about (coarse / n)^3 of one over all items),
  /// the others go where their nearest placed items in the data lie, the layout is scaled to the
  /// whole problem's best, and all are refined from there within max_iterations. The coarse stage
  /// is itself coarse-to-fine while coarse / kLevelRatio >= kSmallestLevel (1000 items: 300, of
  /// them 60 first; 700 items: 210, of them 42 first). 0: all at once. -1: automatic (`matlas
  /// build`'s default, resolved()): 0.3 n from kLargePlacement items on, else 0. With a short refinement of 1000 materials it
  /// reconstructs the data far better than the same time spent on all at once (docs/BENCHMARKS.md).
  /// (The sparse placement's is SparseOptions::coarse.)
  int coarse = 0;
  static constexpr int kCoarseIterations = 600;
  static constexpr int kLevelRatio = 5, kSmallestLevel = 30;
  /// From this many items on, the automatic choices cut the refinement and place coarse-to-fine.
  static constexpr Eigen::Index kLargePlacement = 500;

  /// These options with coarse -1 and max_iterations -1 replaced by their automatic values for n
  /// items (optimize_latent does this itself).
  OptimizeOptions resolved(Eigen::Index n) const;
};

struct OptimizeResult {
  Eigen::MatrixXd latent;       ///< the best latent points found (n x q)
  double value = 0;             ///< L(latent), true units (log_likelihood)
  int iterations = 0;           ///< L-BFGS iterations or Hooke-Jeeves sweeps (all starts)
  int evaluations = 0;          ///< likelihood evaluations, with gradient for L-BFGS (all starts)
  double seconds = 0;           ///< wall time
  std::vector<double> history;  ///< best L after each iteration of the winning start (history[0] = its L(X0))
  std::string stop_reason;      ///< why it stopped, in words
  int best_start = 0;           ///< which start won (0 = X0 itself)
  /// Whether the winning start met a convergence test (gradient norm, relative improvement or no
  /// possible improvement), rather than stopping on the iteration, time or target limit.
  bool converged() const { return stop_reason.rfind("converged", 0) == 0; }
};

/// Maximises log_likelihood over X from X0. Reports progress lines ("iter 12  L = ...") through
/// sink.message() (at most 4 per second, plus the first and the last). L-BFGS uses LBFGSpp
/// (minimising -l) with the strong-Wolfe line search of Nocedal & Wright, guarded so that a failed
/// line search restarts from the best point with a fresh curvature memory. Hooke-Jeeves is the
/// classic pattern search: exploratory moves of step h per coordinate, pattern moves while they
/// improve, h halved when a sweep finds nothing. The result is the best point evaluated.
/// Deterministic. Throws matlas::Error if the problem is malformed, X0 has the wrong shape or is
/// not finite, or K(X0) is not positive definite.
OptimizeResult optimize_latent(const LikelihoodProblem& p, Eigen::MatrixXd X0, const OptimizeOptions& o,
                               ProgressSink& sink);

/// "lbfgs" or "hooke-jeeves".
const char* to_string(Optimizer method);
/// Accepts "lbfgs" (or "l-bfgs") and "hooke-jeeves" (or "hooke_jeeves", "hj"); throws
/// matlas::Error naming the valid choices otherwise.
Optimizer optimizer_from_string(const std::string& name);

}  // namespace matlas::gp
