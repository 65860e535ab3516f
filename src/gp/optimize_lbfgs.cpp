// L-BFGS maximisation of the likelihood with LBFGSpp (which minimises, so the objective is -l).
#include <LBFGS.h>

#include <cmath>
#include <exception>

#include "core/error.h"
#include "gp/optimize_methods.h"

namespace matlas::gp::detail {

namespace {

/// A line search that did not decrease the objective (or threw): restart from the best point.
struct LineSearchFailed {};

/// -l(x) and its gradient for LBFGSpp, x = the column-major flattening of X (n x q).
class NegatedObjective {
public:
  explicit NegatedObjective(OptimizationRun& run) : run_(run), X_(run.count(), run.dim()), G_(run.count(), run.dim()) {}

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    X_ = Eigen::Map<const Eigen::MatrixXd>(x.data(), X_.rows(), X_.cols());
    const double value = run_.evaluate(X_, &G_);
    grad = -Eigen::Map<const Eigen::VectorXd>(G_.data(), G_.size());
    return -value;
  }

  /// Called by GuardedLineSearch once per L-BFGS iteration.
  void end_iteration() { run_.end_iteration(true); }

private:
  OptimizationRun& run_;
  Eigen::MatrixXd X_, G_;
};

/// LBFGSpp's Nocedal-Wright strong-Wolfe line search, plus the per-iteration hook, plus a guard:
/// it can return (at its trial limit) a point that is worse than the start, or throw on numeric
/// trouble; either becomes LineSearchFailed, which the driver answers with a restart.
template <typename Scalar>
class GuardedLineSearch {
public:
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

  template <typename Foo>
  static void LineSearch(Foo& f, Scalar& fx, Vector& x, Vector& grad, Scalar& step, const Vector& drt,
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

}  // namespace

std::string run_lbfgs(OptimizationRun& run) {
  LBFGSpp::LBFGSParam<double> param;
  // 20 correction pairs: on the realistic databases (83 and 100 materials, q = 2 and 5) 10-30 %
  // fewer iterations than 10, and every default build converged (docs/BENCHMARKS.md).
  param.m = 20;
  param.epsilon = run.options().tolerance * std::max(1.0, std::abs(run.initial_value()));
  param.epsilon_rel = 0;
  param.past = 0;            // the relative-improvement test is done in end_iteration
  param.max_iterations = 0;  // and the iteration limit too
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
  param.max_linesearch = 40;
  NegatedObjective objective(run);
  double last_restart_value = -std::numeric_limits<double>::infinity();
  for (;;) {
    Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(run.best().data(), run.best().size());
    last_restart_value = run.best_value();
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
      if (!(run.best_value() > last_restart_value)) return "converged: the line search cannot improve L";
    }
  }
}

}  // namespace matlas::gp::detail
