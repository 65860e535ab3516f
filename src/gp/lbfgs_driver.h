#pragma once
// Internal to src/gp: LBFGSpp's parameters from MinimizeOptions (minimize.h), and L-BFGS with a
// guarded line search and restarts from the best point, shared by the exact (optimize_lbfgs.cpp)
// and the sparse (sparse_optimize.cpp) latent optimisations. LBFGSpp minimises, so objectives
// return -l.
#include <LBFGS.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

#include "gp/minimize.h"
#include "gp/optimize_run.h"

namespace matlas::gp::detail {

/// LBFGSpp's parameters for o (the line search's own condition is left to the caller).
inline LBFGSpp::LBFGSParam<double> lbfgs_param(const MinimizeOptions& o) {
  LBFGSpp::LBFGSParam<double> param;
  param.m = o.memory;
  param.epsilon = o.gradient_tolerance;
  param.epsilon_rel = o.relative_gradient_tolerance;
  param.max_iterations = o.max_iterations;
  param.max_linesearch = o.max_line_search;
  return param;
}

/// A line search that did not decrease the objective (or threw): restart from the best point.
struct LineSearchFailed {};

/// LBFGSpp's Nocedal-Wright strong-Wolfe line search, plus the per-iteration hook, plus a guard:
/// it can return (at its trial limit) a point that is worse than the start, or throw on numeric
/// trouble; either becomes LineSearchFailed, which the driver answers with a restart.
template <typename Scalar>
class GuardedLineSearch {
public:
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

  template <typename Objective>
  static void LineSearch(Objective& f, Scalar& fx, Vector& x, Vector& grad, Scalar& step, const Vector& drt,
                         const Vector& xp, const LBFGSpp::LBFGSParam<Scalar>& param) {
    const Scalar fx_start = fx;
    try {
      LBFGSpp::LineSearchNocedalWright<Scalar>::LineSearch(f, fx, x, grad, step, drt, xp, param);
    } catch (const std::exception&) {  // numeric trouble, descent check, or K not PD at a trial point
      throw LineSearchFailed{};
    }
    if (!(fx < fx_start) || !std::isfinite(fx)) throw LineSearchFailed{};
    f.end_iteration();
  }
};

/// Runs L-BFGS until a stop rule fires and returns the reason in words. The objective provides
///   double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad)   -l and its gradient
///   void end_iteration()               once per iteration; throws StopRequested to end the run
///   Eigen::VectorXd best_point() const, double best_value() const (normalised l)
/// `tolerance` and `initial_value` set the gradient test (relative to |l| at the start).
template <typename Objective>
std::string run_restarting_lbfgs(Objective& objective, double tolerance, double initial_value) {
  MinimizeOptions o;
  // 20 correction pairs: on the realistic databases (83 and 100 materials, q = 2 and 5) 10-30 %
  // fewer iterations than 10, and every default build converged (docs/BENCHMARKS.md).
  o.memory = 20;
  o.gradient_tolerance = tolerance * std::max(1.0, std::abs(initial_value));
  o.relative_gradient_tolerance = 0;
  o.max_iterations = 0;  // the iteration limit is done in end_iteration
  o.max_line_search = 40;
  LBFGSpp::LBFGSParam<double> param = lbfgs_param(o);
  param.past = 0;  // and the relative-improvement test too
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
  for (;;) {
    Eigen::VectorXd x = objective.best_point();
    const double restart_value = objective.best_value();
    LBFGSpp::LBFGSSolver<double, GuardedLineSearch> solver(param);
    double fx = 0;
    try {
      solver.minimize(objective, x, fx);
      return "converged: gradient norm below tolerance";
    } catch (const StopRequested& stop) {
      return stop.reason;
    } catch (const LineSearchFailed&) {
      // Restart with a fresh curvature memory from the best point, unless the last restart did
      // not get anywhere either.
      if (!(objective.best_value() > restart_value)) return "converged: the line search cannot improve L";
    }
  }
}

}  // namespace matlas::gp::detail
