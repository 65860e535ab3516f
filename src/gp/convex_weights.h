#pragma once
// Convex interpolation weights: the GP's affine combination of the inputs projected onto the
// probability simplex in the metric of the data.
//
// The GP posterior mean is an affine combination of the inputs, m(x) = sum_i g_i(x) z_i with
// sum_i g_i = 1 (g = w + (1 - sum w) / n for the weights w = K^-1 k(x) of the centred data), and
// its coefficients can be negative: m(x) can then have negative values and more energy than any
// input. ConvexProjection replaces g by the closest convex combination in the metric A,
//
//     c(g) = argmin_{c >= 0, sum c = 1} (c - g)^T A (c - g),   A = S / (tr S / n) + ridge I,
//
// with S the centred Gram matrix of the inputs (in the space used to place them). Properties, all
// tested:
// - convex: c >= 0 and sum c = 1, so every value of m(x) lies between the inputs' smallest and
//   largest values at that bin: no negative value (for non-negative inputs), reciprocity kept, and
//   any linear functional (directional albedo, an image) at most the inputs' largest;
// - exact at the data: g = e_i is already convex, so c = e_i;
// - continuous (Lipschitz): the projection onto a convex set in the A-norm is non-expansive in
//   that norm, |c(g) - c(g')|_A <= |g - g'|_A, and ridge > 0 makes A positive definite;
// - where g is convex already (near the data), c = g: the GP unchanged. (With many inputs that is
//   rare away from the data points: some GP weight is slightly negative almost everywhere.)
// The quadratic programme (n variables, one equality, n bounds) is solved exactly by a primal
// active-set method (Nocedal & Wright, Numerical Optimization, Algorithm 16.3, freeing up to
// kFreedAtOnce bounds per iteration instead of one), started from the clipped and renormalised
// g; it ends in a few iterations since the solution is sparse.
//
// Many points at once (a map's grid): neighbouring points have nearly equal convex weights, so
// project_batch starts each solve from the previous point's solution and free set, a feasible
// start (all problems share the simplex) a change or two from the optimum (2.8 active-set
// iterations per cell on average on a 128 x 128 map of 100 materials), and keeps the Cholesky
// factor of A_FF from point to point, updated by one row per freed or bound coefficient
// (O(|F|^2)) instead of refactorised per iteration (O(|F|^3)). The method ends at the same KKT
// point whatever the start (A is positive definite, the projection unique), so the batch equals
// project() per column.
#include <cstddef>
#include <memory>

#include <Eigen/Core>
#include <vector>

namespace matlas::gp {

class ConvexProjection {
  /// The active-set method's iterate: a feasible c (on the simplex) and its free set (c_i > 0
  /// only where free), and the scratch of its solves.
  struct Iterate;

public:
  /// Bounds freed per active-set iteration, the most negative multipliers first. Freeing several
  /// keeps the method exact (the objective still falls strictly from one free-set optimum to the
  /// next, so no free set repeats) and saves iterations where the free set changes by many
  /// coefficients from one point to its neighbour (hundreds of free coefficients at n = 1000).
  static constexpr std::size_t kFreedAtOnce = 8;
  /// Default relative ridge: A = S / (tr S / n) + kDefaultRidge I.
  static constexpr double kDefaultRidge = 1e-2;

  /// gram: the centred Gram matrix S (n x n, symmetric PSD); ridge > 0 relative to tr(S)/n.
  /// Throws matlas::Error if S is not square and finite or ridge is not > 0.
  explicit ConvexProjection(const Eigen::MatrixXd& gram, double ridge = kDefaultRidge);

  int count() const { return static_cast<int>(A_.rows()); }
  double ridge() const { return ridge_; }
  const Eigen::MatrixXd& metric() const { return A_; }  ///< A

  /// c(g) for affine coefficients g (length n, sum 1 up to rounding; throws otherwise), settled
  /// on its support (below): the bits depend on g alone.
  Eigen::VectorXd project(const Eigen::Ref<const Eigen::VectorXd>& g) const;

  /// The convex weights for the GP weights w of the centred data: c(g) of their affine
  /// coefficients g = w + (1 - sum w) / n (core/combination.h, Combination::affine).
  Eigen::VectorXd from_centred(const Eigen::Ref<const Eigen::VectorXd>& w) const;

  /// What a sequence of solves at nearby points shares: each starts from the previous one's
  /// solution and free set (as project_batch's columns do) and ends, in fewer iterations, at the
  /// same optimum as a cold solve; from_centred(w, warm) settles it on its support as project()
  /// does, so that it gives the cold solve's weights bit for bit (where both find the same
  /// support: always but for coefficients that are 0 to rounding). One per sequence (not shared
  /// between threads); empty at first.
  class WarmStart {
  public:
    WarmStart();
    ~WarmStart();
    WarmStart(WarmStart&&) noexcept;
    WarmStart& operator=(WarmStart&&) noexcept;

  private:
    friend class ConvexProjection;
    std::unique_ptr<Iterate> it_;
  };
  /// from_centred(w), started from `warm` (then holding this solve's state).
  Eigen::VectorXd from_centred(const Eigen::Ref<const Eigen::VectorXd>& w, WarmStart& warm) const;

  /// c(g) of every column of G (n x m), in place: project() per column, each solve started from
  /// the solution of the column before it. The columns come in runs of `run` consecutive columns
  /// along which neighbouring columns are close (a grid's rows), each run's first column close to
  /// the previous run's first (the cell above): the runs' first columns are solved in turn, then
  /// the runs in parallel (core/parallel.h). Any order gives the same result, only slower.
  /// Throws as project() does for a bad column; run <= 0 means one run.
  void project_batch(Eigen::Ref<Eigen::MatrixXd> G, Eigen::Index run) const;
  /// The same for GP weights of the centred data (columns of W, n x m), in place: from_centred()
  /// per column.
  void from_centred_batch(Eigen::Ref<Eigen::MatrixXd> W, Eigen::Index run) const;

private:
  /// Throws unless g has n finite entries summing to 1; returns the sum.
  double check(const Eigen::Ref<const Eigen::VectorXd>& g) const;
  /// Runs the active-set method for b = A g from `it` (feasible) to the optimum, left in `it`.
  void solve(const Eigen::VectorXd& b, Iterate& it) const;
  /// The optimum c_F (into it.cF) of the equality-constrained problem on the free set, and its
  /// multiplier nu.
  double free_set_optimum(const Eigen::VectorXd& b, Iterate& it) const;
  /// At most kFreedAtOnce bounds whose multipliers (A c - b)_j - nu are below -tolerance, the
  /// most negative first, into it.negative: empty when c (it.c, the free-set optimum) is optimal.
  void negative_multipliers(const Eigen::VectorXd& b, double nu, double tolerance, Iterate& it) const;
  /// c(g) into g, started from `it` (the previous solution; cold when it holds none), which then
  /// holds this solution (left as it was where g is convex already). b: A g if known (n values).
  void project_from(Eigen::Ref<Eigen::VectorXd> g, Iterate& it, const double* b = nullptr) const;
  /// The optimum c (from project_from, for b = A g) recomputed on its support from a fresh
  /// factorisation in index order, so that a point's weights do not depend on where its solve
  /// started (cold or warm: the same support gives the same bits). O(|S|^3 / 3).
  void settle(Eigen::Ref<Eigen::VectorXd> c, const Eigen::VectorXd& b) const;

  Eigen::MatrixXd A_;
  double ridge_;
};

}  // namespace matlas::gp
