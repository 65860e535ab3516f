#pragma once
// Internal to src/gp: the bookkeeping shared by the optimisers (evaluation counting, best point,
// history, progress lines, time/iteration/target limits). Not part of the public API.
#include <chrono>
#include <optional>
#include <string>

#include "gp/optimize.h"

namespace matlas::gp::detail {

/// Thrown by OptimizationRun to end an optimisation early; deliberately not a std::exception so
/// that no generic handler (e.g. inside LBFGSpp) swallows it.
struct StopRequested {
  std::string reason;
};

class OptimizationRun {
public:
  OptimizationRun(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, const OptimizeOptions& o,
                  ProgressSink& sink);

  int count() const { return static_cast<int>(best_.rows()); }
  int dim() const { return static_cast<int>(best_.cols()); }
  const OptimizeOptions& options() const { return options_; }
  const Eigen::MatrixXd& best() const { return best_; }
  double best_value() const { return best_value_; }  ///< normalised l
  double initial_value() const { return initial_value_; }
  int iterations() const { return iterations_; }
  const LikelihoodEvaluator& evaluator() const { return evaluator_; }
  /// Compared as log-likelihoods, the unit of the target: converting the target to the
  /// normalised scale instead rounds, and a target equal to L(X0) could then read as missed.
  bool target_reached() const { return evaluator_.to_log_likelihood(best_value_) >= options_.target_value; }

  /// Normalised l(X) (and dl/dX when gradient != nullptr); tracks the best point. Throws
  /// StopRequested when the time limit or the target value is reached, matlas::Error if K is not
  /// positive definite.
  double evaluate(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient = nullptr);

  /// Ends one iteration: records history, reports progress, and throws StopRequested at the
  /// iteration limit or (when check_improvement) when l improved by at most tolerance*max(1,|l|)
  /// over the last 3 iterations.
  void end_iteration(bool check_improvement);

  /// The result, with the best point and its true L.
  OptimizeResult finish(std::string reason);

private:
  void report(bool force);
  double elapsed() const;

  LikelihoodEvaluator evaluator_;
  OptimizeOptions options_;
  ProgressSink& sink_;
  Eigen::MatrixXd best_;
  double best_value_;
  double initial_value_;
  int iterations_ = 0;
  int evaluations_ = 0;
  std::vector<double> history_normalized_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_report_{};
};

/// Several starts of one optimisation (OptimizeOptions::starts), the dense and the sparse one's:
/// each start's share of the time limit, the totals over the starts, the best result kept.
class BestOfStarts {
public:
  explicit BestOfStarts(const OptimizeOptions& o) : options_(o) {}
  /// The options of start k, its time limit what is left of the whole; nullopt once the time is
  /// spent (never for the first start).
  std::optional<OptimizeOptions> start(int k) const;
  /// Counts start k's result; true when it is the best so far (the caller keeps what goes with it).
  bool add(OptimizeResult r, int k);
  /// The last start reached the target value or the time limit: no more starts.
  bool done() const { return done_; }
  /// The best result with the iterations and evaluations of all starts, the time since the
  /// first, and (with several starts) which one won.
  OptimizeResult finish();

private:
  double elapsed() const;

  OptimizeOptions options_;
  std::chrono::steady_clock::time_point begin_ = std::chrono::steady_clock::now();
  OptimizeResult best_;
  int iterations_ = 0, evaluations_ = 0;
  bool any_ = false, done_ = false;
};

}  // namespace matlas::gp::detail
