#include "gp/initialize.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace matlas::gp {

namespace {

// Normalised log-likelihood of a * X; -inf where K is not positive definite (never for nugget > 0).
double scaled_value(const std::function<double(const Eigen::MatrixXd&)>& value, const Eigen::MatrixXd& X,
                    double log_a) {
  try {
    return value(std::exp(log_a) * X);
  } catch (const Error&) {
    return -std::numeric_limits<double>::infinity();
  }
}

}  // namespace

double best_scale_factor(LikelihoodEvaluator& evaluator, const Eigen::MatrixXd& X, double a_min, double a_max,
                         int scan, double tolerance) {
  return best_scale_factor([&evaluator](const Eigen::MatrixXd& Y) { return evaluator.normalized(Y); }, X, a_min, a_max,
                           scan, tolerance);
}

double best_scale_factor(const std::function<double(const Eigen::MatrixXd&)>& evaluator, const Eigen::MatrixXd& X,
                         double a_min, double a_max, int scan, double tolerance) {
  if (!(a_min > 0) || !(a_max > a_min)) throw Error("best_scale_factor: need 0 < a_min < a_max");
  if (scan < 2 || !(tolerance > 0)) throw Error("best_scale_factor: need a scan of at least 2 values and a tolerance > 0");
  // Coarse scan: the likelihood of a scaled point set is smooth in log a but need not be
  // unimodal over many decades, so bracket the best grid point first.
  const double lo = std::log(a_min), hi = std::log(a_max);
  const double step = (hi - lo) / (scan - 1);
  int best = 0;
  double best_value = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < scan; ++i) {
    const double v = scaled_value(evaluator, X, lo + step * i);
    if (v > best_value) best_value = v, best = i;
  }
  if (!std::isfinite(best_value)) throw Error("best_scale_factor: the likelihood is not finite at any scale");
  // Golden-section search on [best - 1, best + 1] grid steps.
  double a = lo + step * std::max(0, best - 1), b = lo + step * std::min(scan - 1, best + 1);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = scaled_value(evaluator, X, c), fd = scaled_value(evaluator, X, d);
  for (int it = 0; it < 40 && b - a > tolerance; ++it) {
    if (fc >= fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a), fc = scaled_value(evaluator, X, c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a), fd = scaled_value(evaluator, X, d);
    }
  }
  double result = 0.5 * (a + b);
  // Never return something worse than the best grid point.
  if (scaled_value(evaluator, X, result) < best_value) result = lo + step * best;
  return std::exp(result);
}

Eigen::MatrixXd pca_initialization(const LikelihoodProblem& p, int q, bool search_scale) {
  LikelihoodEvaluator evaluator(p);  // validates the problem
  const Eigen::Index n = p.gram.rows();
  if (q < 1) throw Error("pca_initialization: latent dimension must be >= 1 (got " + std::to_string(q) + ")");
  // The principal axes of S / sigma (so that they do not depend on the data scale), each scaled by
  // the square root of its eigenvalue: the last columns of the likelihood's factor R (S / sigma =
  // R R^T, eigenvalues ascending; those below 1e-13 of the largest are not there: zero axes).
  const Eigen::MatrixXd& R = evaluator.factor().R;
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, q);
  const Eigen::Index available = std::min<Eigen::Index>(q, R.cols());
  for (Eigen::Index k = 0; k < available; ++k) {
    Eigen::VectorXd u = R.col(R.cols() - 1 - k);
    Eigen::Index imax = 0;
    u.cwiseAbs().maxCoeff(&imax);
    if (u[imax] < 0) u = -u;
    X.col(k) = u;
  }
  const double rms = std::sqrt(X.squaredNorm() / static_cast<double>(n));
  if (!(rms > 0)) return X;  // no variation at all: nothing to scale
  const double unit = p.kernel.lengthscale / rms;  // scale with RMS radius = lengthscale
  if (!search_scale) return unit * X;
  const double a = best_scale_factor(evaluator, X, unit * 1e-3, unit * 1e3);
  return a * X;
}

}  // namespace matlas::gp
