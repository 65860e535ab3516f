// L-BFGS maximisation of the exact likelihood (gp/lbfgs_driver.h runs LBFGSpp on -l).
#include "gp/lbfgs_driver.h"
#include "gp/optimize_methods.h"

namespace matlas::gp::detail {

namespace {

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

  void end_iteration() { run_.end_iteration(true); }
  Eigen::VectorXd best_point() const { return Eigen::Map<const Eigen::VectorXd>(run_.best().data(), run_.best().size()); }
  double best_value() const { return run_.best_value(); }

private:
  OptimizationRun& run_;
  Eigen::MatrixXd X_, G_;
};

}  // namespace

std::string run_lbfgs(OptimizationRun& run) {
  NegatedObjective objective(run);
  return run_restarting_lbfgs(objective, run.options().tolerance, run.initial_value());
}

}  // namespace matlas::gp::detail
