#pragma once
// The minimisers of matlas, behind one options type (MinimizeOptions):
// - L-BFGS (LBFGSpp, backtracking line search) for smooth objectives with a gradient: the
//   projection of a material onto a map (manifold/project.h). The latent optimisation
//   (optimize.h) runs the same L-BFGS from the same options with a guarded strong-Wolfe line
//   search and restarts from the best point (lbfgs_driver.h), and offers Hooke-Jeeves, the paper's
//   pattern search, beside it;
// - Nelder-Mead, derivative-free, for the small non-smooth searches in latent space (the
//   projection of a material measured in a Gram, eval/latent_fit.h; the fit of sparse samples,
//   acquisition/sparse_fit.h), whose objectives go through the convex projection of the weights
//   and have kinks, and for the analytic fits of artist/pbr_fit.h.
// Both are deterministic.
#include <functional>
#include <optional>

#include <Eigen/Core>

namespace matlas::gp {

struct MinimizeOptions {
  /// L-BFGS: iterations (0: no limit); Nelder-Mead: evaluations of f (> 0).
  int max_iterations = 200;
  /// L-BFGS: converged when |grad f| <= max(gradient_tolerance, relative_gradient_tolerance |x|).
  double gradient_tolerance = 1e-8;
  double relative_gradient_tolerance = 1e-8;
  int memory = 6;            ///< L-BFGS: correction pairs kept
  int max_line_search = 40;  ///< L-BFGS: trial steps per line search
  /// Nelder-Mead: the initial simplex's size (x0 + step e_k); converged when the simplex's values
  /// agree to value_tolerance (relative) and its extent is below 1e-9 of |x|.
  double step = 0.1;
  double value_tolerance = 1e-10;

  /// Nelder-Mead's options: initial simplex size, evaluations, value tolerance.
  static MinimizeOptions nelder_mead(double step, int evaluations, double value_tolerance = 1e-10) {
    MinimizeOptions o;
    o.max_iterations = evaluations;
    o.step = step;
    o.value_tolerance = value_tolerance;
    return o;
  }
};

/// f(x, grad): the value, and the gradient into grad.
using ObjectiveWithGradient = std::function<double(const Eigen::VectorXd&, Eigen::VectorXd&)>;

/// Minimises f by L-BFGS from x, in place: the value at the end, or none when a line search failed
/// (numeric trouble, no descent); x is then the last point tried, possibly not finite.
std::optional<double> minimize_lbfgs(const ObjectiveWithGradient& f, Eigen::VectorXd& x, const MinimizeOptions& o);

/// Minimises f over R^d by Nelder-Mead from x0 (reflection 1, expansion 2, contraction 1/2, shrink
/// 1/2) with o.step, o.max_iterations (evaluations) and o.value_tolerance. Returns the best point
/// seen.
Eigen::VectorXd minimize_nelder_mead(const std::function<double(const Eigen::VectorXd&)>& f, Eigen::VectorXd x0,
                                     const MinimizeOptions& o);

}  // namespace matlas::gp
