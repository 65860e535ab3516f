#include "gp/optimize_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/check.h"
#include "core/error.h"

namespace matlas::gp::detail {

OptimizationRun::OptimizationRun(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, const OptimizeOptions& o,
                                 ProgressSink& sink)
    : evaluator_(p), options_(o), sink_(sink), best_(X0) {
  if (X0.rows() != evaluator_.count() || X0.cols() == 0)
    throw Error("optimize_latent: X0 is " + std::to_string(X0.rows()) + " x " + std::to_string(X0.cols()) +
                " but the Gram matrix has " + std::to_string(evaluator_.count()) + " items");
  if (!(o.tolerance >= 0)) throw Error("optimize_latent: tolerance must be >= 0");
  if (o.max_iterations < 0) throw Error("optimize_latent: max_iterations must be >= 0");
  if (!(o.time_limit_seconds >= 0)) throw Error("optimize_latent: time_limit_seconds must be >= 0");
  best_value_ = evaluator_.normalized(X0);  // throws if K(X0) is not positive definite
  ++evaluations_;
  initial_value_ = best_value_;
  history_normalized_.push_back(best_value_);
  report(true);
}

double OptimizationRun::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double OptimizationRun::evaluate(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient) {
  if (options_.time_limit_seconds > 0 && elapsed() > options_.time_limit_seconds)
    throw StopRequested{"time limit reached"};
  const double value = evaluator_.normalized(X, gradient);
  ++evaluations_;
  if (value > best_value_) {
    best_value_ = value;
    best_ = X;
    if (target_reached()) {
      history_normalized_.push_back(best_value_);
      throw StopRequested{"target value reached"};
    }
  }
  return value;
}

void OptimizationRun::end_iteration(bool check_improvement) {
  ++iterations_;
  history_normalized_.push_back(best_value_);
  report(false);
  if (iterations_ >= options_.max_iterations) throw StopRequested{"iteration limit reached"};
  constexpr int kWindow = 3;
  if (check_improvement && iterations_ >= kWindow) {
    const double before = history_normalized_[history_normalized_.size() - 1 - kWindow];
    if (best_value_ - before <= options_.tolerance * std::max(1.0, std::abs(best_value_)))
      throw StopRequested{"converged: relative improvement below tolerance"};
  }
}

void OptimizationRun::report(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_report_ < std::chrono::milliseconds(250)) return;
  last_report_ = now;
  char line[160];
  std::snprintf(line, sizeof line, "%s iter %d  L = %.10g  (evaluations %d, %.2f s)", to_string(options_.method),
                iterations_, evaluator_.to_log_likelihood(best_value_), evaluations_, elapsed());
  sink_.message(line);
}

OptimizeResult OptimizationRun::finish(std::string reason) {
  OptimizeResult r;
  r.latent = best_;
  r.value = evaluator_.to_log_likelihood(best_value_);
  r.iterations = iterations_;
  r.evaluations = evaluations_;
  r.seconds = elapsed();
  r.history.reserve(history_normalized_.size());
  for (double v : history_normalized_) r.history.push_back(evaluator_.to_log_likelihood(v));
  r.stop_reason = std::move(reason);
  report(true);
  sink_.message(std::string(to_string(options_.method)) + " stopped: " + r.stop_reason);
  return r;
}

double BestOfStarts::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin_).count();
}

std::optional<OptimizeOptions> BestOfStarts::start(int k) const {
  OptimizeOptions one = options_;
  if (options_.time_limit_seconds > 0) {
    const double used = elapsed();
    if (k > 0 && used >= options_.time_limit_seconds) return std::nullopt;
    one.time_limit_seconds = std::max(options_.time_limit_seconds - used, 1e-9);
  }
  return one;
}

bool BestOfStarts::add(OptimizeResult r, int k) {
  iterations_ += r.iterations;
  evaluations_ += r.evaluations;
  done_ = r.stop_reason == "target value reached" || r.stop_reason == "time limit reached";
  if (any_ && !(r.value > best_.value)) return false;
  best_ = std::move(r);
  best_.best_start = k;
  any_ = true;
  return true;
}

OptimizeResult BestOfStarts::finish() {
  MATLAS_CHECK(any_, "at least one start ran");
  OptimizeResult best = std::move(best_);
  best.iterations = iterations_;
  best.evaluations = evaluations_;
  best.seconds = elapsed();
  if (options_.starts > 1)
    best.stop_reason += " (best of " + std::to_string(options_.starts) + " starts: start " +
                        std::to_string(best.best_start + 1) + ")";
  return best;
}

}  // namespace matlas::gp::detail
