// Hooke-Jeeves pattern search (Hooke & Jeeves 1961), as used by Soler et al. 2018 to fit the
// latent points: derivative-free, one value-only likelihood evaluation per trial move.
#include <cmath>
#include <limits>

#include "core/error.h"

#include "gp/optimize_methods.h"

namespace matlas::gp::detail {

namespace {

/// l at a trial point; a trial where K is not positive definite (possible only with nugget 0 when
/// two points meet) counts as no improvement.
double trial_value(OptimizationRun& run, const Eigen::MatrixXd& point) {
  try {
    return run.evaluate(point);
  } catch (const Error&) {
    return -std::numeric_limits<double>::infinity();
  }
}

/// Exploratory moves around `point` (value `value`): each coordinate in turn tries +h, then -h,
/// keeping a move when it improves l. Updates point and value in place; one iteration.
void explore(OptimizationRun& run, Eigen::MatrixXd& point, double& value, double h) {
  for (Eigen::Index k = 0; k < point.size(); ++k) {
    double& coordinate = point.data()[k];
    const double original = coordinate;
    coordinate = original + h;
    double trial = trial_value(run, point);
    if (trial > value) {
      value = trial;
      continue;
    }
    coordinate = original - h;
    trial = trial_value(run, point);
    if (trial > value) {
      value = trial;
      continue;
    }
    coordinate = original;
  }
  run.end_iteration(false);
}

}  // namespace

std::string run_hooke_jeeves(OptimizationRun& run) {
  const Eigen::MatrixXd& X0 = run.best();
  const double radius =
      std::sqrt((X0.rowwise() - X0.colwise().mean()).squaredNorm() / static_cast<double>(X0.rows()));
  const double h0 = 0.1 * (radius > 0 ? radius : run.evaluator().kernel().lengthscale);
  const double h_min = h0 * std::sqrt(run.options().tolerance);
  double h = h0;
  Eigen::MatrixXd base = X0;
  double base_value = run.best_value();
  try {
    while (h >= h_min) {
      Eigen::MatrixXd x = base;
      double x_value = base_value;
      explore(run, x, x_value, h);
      if (!(x_value > base_value)) {
        h *= 0.5;
        continue;
      }
      // Pattern moves: jump along the last improvement and explore there, while that improves.
      for (;;) {
        Eigen::MatrixXd pattern = 2.0 * x - base;
        base = x;
        base_value = x_value;
        double pattern_value = trial_value(run, pattern);
        explore(run, pattern, pattern_value, h);
        if (!(pattern_value > base_value)) break;
        x = pattern;
        x_value = pattern_value;
      }
    }
  } catch (const StopRequested& stop) {
    return stop.reason;
  }
  return "converged: step below sqrt(tolerance) * initial step";
}

}  // namespace matlas::gp::detail
