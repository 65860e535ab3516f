#include "gp/optimize.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "gp/coarse_placement.h"
#include "gp/initialize.h"
#include "gp/optimize_methods.h"
#include "gp/optimize_run.h"

namespace matlas::gp {

namespace {

/// Scale factor of start k: 1, 2^-1/2, 2^1/2, 2^-1, 2^1, ...
double start_scale(int k) {
  if (k == 0) return 1.0;
  const double exponent = 0.5 * ((k + 1) / 2);
  return std::exp2(k % 2 == 1 ? -exponent : exponent);
}

OptimizeResult optimize_one(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, const OptimizeOptions& o,
                            ProgressSink& sink) {
  detail::OptimizationRun run(p, X0, o, sink);
  if (run.target_reached()) return run.finish("target value reached");
  if (o.max_iterations == 0) return run.finish("iteration limit reached");
  switch (o.method) {
    case Optimizer::lbfgs: return run.finish(detail::run_lbfgs(run));
    case Optimizer::hooke_jeeves: return run.finish(detail::run_hooke_jeeves(run));
  }
  throw Error("optimize_latent: unknown optimizer");
}

/// Keeps a start's progress lines, to be replayed in the order of the starts.
class RecordedProgress final : public ProgressSink {
public:
  void update(const std::string&, std::uint64_t, std::uint64_t) override {}
  void message(const std::string& line) override { lines.push_back(line); }
  void finish(const std::string&) override {}
  std::vector<std::string> lines;
};

std::string start_message(int k, int starts, double scale) {
  return "start " + std::to_string(k + 1) + "/" + std::to_string(starts) + " (X0 scaled by " + std::to_string(scale) +
         ")";
}

Eigen::MatrixXd scaled_start(const Eigen::MatrixXd& X0, const Eigen::RowVectorXd& centroid, int k) {
  return (start_scale(k) * (X0.rowwise() - centroid)).rowwise() + centroid;
}

/// All starts at once, on up to `threads` threads. Each start is independent and deterministic,
/// so the results are those of running them one after the other; only used when no start can
/// end the others early (no time limit, no target), so the same starts run as serially.
std::vector<OptimizeResult> run_starts_concurrently(const LikelihoodProblem& p, const Eigen::MatrixXd& X0,
                                                    const OptimizeOptions& o, ProgressSink& sink, int threads) {
  const Eigen::RowVectorXd centroid = X0.colwise().mean();
  const auto starts = static_cast<std::size_t>(o.starts);
  std::vector<std::optional<OptimizeResult>> results(starts);
  std::vector<RecordedProgress> progress(starts);
  std::vector<std::exception_ptr> errors(starts);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t k; (k = next.fetch_add(1)) < starts;) {
      try {
        results[k] = optimize_one(p, scaled_start(X0, centroid, static_cast<int>(k)), o, progress[k]);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    }
  };
  {
    std::vector<std::jthread> pool;
    for (int t = 1; t < std::min(threads, o.starts); ++t) pool.emplace_back(work);
    work();
  }
  std::vector<OptimizeResult> out;
  for (std::size_t k = 0; k < starts; ++k) {
    sink.message(start_message(static_cast<int>(k), o.starts, start_scale(static_cast<int>(k))));
    for (const std::string& line : progress[k].lines) sink.message(line);
    if (errors[k]) std::rethrow_exception(errors[k]);  // the error a serial run would have met first
    out.push_back(std::move(*results[k]));
  }
  return out;
}

/// optimize_latent without a coarse stage: the starts from X0 (concurrently when none can stop the
/// others), the best kept.
OptimizeResult optimize_all_at_once(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, const OptimizeOptions& o,
                                    ProgressSink& sink) {
  if (o.starts == 1) return optimize_one(p, X0, o, sink);

  // Starts in parallel when none can stop the others (a time limit or target is checked serially):
  // one thread per start (up to 16), so that 3 starts on 2 cores take 1.5 starts' time, not 2.
  detail::BestOfStarts starts(o);
  const int threads = std::min(o.starts, 16);
  const bool concurrent =
      std::thread::hardware_concurrency() > 1 && o.time_limit_seconds == 0 && std::isinf(o.target_value);
  std::vector<OptimizeResult> done_starts;
  if (concurrent) done_starts = run_starts_concurrently(p, X0, o, sink, threads);

  const Eigen::RowVectorXd centroid = X0.colwise().mean();
  for (int k = 0; k < o.starts && !starts.done(); ++k) {
    if (concurrent) {
      starts.add(std::move(done_starts[static_cast<std::size_t>(k)]), k);
      continue;
    }
    const std::optional<OptimizeOptions> one = starts.start(k);
    if (!one) break;
    sink.message(start_message(k, o.starts, start_scale(k)));
    starts.add(optimize_one(p, scaled_start(X0, centroid, k), *one, sink), k);
  }
  return starts.finish();
}

OptimizeResult coarse_to_fine(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, const OptimizeOptions& o,
                              ProgressSink& sink);

/// optimize_latent with a coarse stage (o.coarse in (0, n)): the starts on the subset (itself
/// placed coarse-to-fine when it is large enough), the interpolation of the others, one refinement
/// of all.
OptimizeResult coarse_to_fine(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, const OptimizeOptions& o,
                              ProgressSink& sink) {
  const auto begin = std::chrono::steady_clock::now();
  const std::vector<Eigen::Index> rows = coarse_subset(X0.rows(), o.coarse);
  sink.message("coarse placement: " + std::to_string(rows.size()) + " of " + std::to_string(X0.rows()) + " items");
  OptimizeOptions first = o;  // the target is the whole problem's: not for the subset's objective
  first.target_value = std::numeric_limits<double>::infinity();
  first.max_iterations = std::max(o.max_iterations, OptimizeOptions::kCoarseIterations);
  // The subset's start: its rows of X0, about their centroid, scaled to the subset's best.
  const LikelihoodProblem subset = subset_problem(p, rows);
  Eigen::MatrixXd S0 = X0(rows, Eigen::all);
  S0 = S0.rowwise() - S0.colwise().mean();
  if (S0.norm() > 0) {
    LikelihoodEvaluator evaluator(subset);
    S0 *= best_scale_factor(evaluator, S0, 0.1, 10.0);
  }
  // Itself coarse-to-fine while a level of coarse / kLevelRatio items keeps kSmallestLevel or more.
  first.coarse = o.coarse / OptimizeOptions::kLevelRatio >= OptimizeOptions::kSmallestLevel
                     ? o.coarse / OptimizeOptions::kLevelRatio
                     : 0;
  const OptimizeResult coarse =
      first.coarse > 0 ? coarse_to_fine(subset, S0, first, sink) : optimize_all_at_once(subset, S0, first, sink);
  // The interpolated layout about its centroid, scaled to the whole problem's best (n items
  // spread wider than the subset's: their repulsion and covariance want room).
  Eigen::MatrixXd X1 = interpolate_layout(p.gram, rows, coarse.latent);
  X1 = X1.rowwise() - X1.colwise().mean();
  if (X1.norm() > 0) {  // else a degenerate subset layout: nothing to scale
    LikelihoodEvaluator evaluator(p);
    const double a = best_scale_factor(evaluator, X1, 0.25, 4.0, 9, 1e-2);  // to 1 %: the refinement follows
    sink.message("coarse placement: the others interpolated, the layout scaled by " + std::to_string(a));
    X1 *= a;
  }
  sink.message("refinement of all " + std::to_string(X0.rows()) + " items");
  const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return with_coarse_stage(optimize_one(p, X1, refinement_options(o, spent), sink), coarse, begin);
}

}  // namespace

OptimizeResult optimize_latent(const LikelihoodProblem& p, Eigen::MatrixXd X0, const OptimizeOptions& o,
                               ProgressSink& sink) {
  if (!X0.allFinite()) throw Error("optimize_latent: the initial latent points contain NaN or infinity");
  if (o.starts < 1) throw Error("optimize_latent: starts must be >= 1 (got " + std::to_string(o.starts) + ")");
  if (o.coarse < -1) throw Error("optimize_latent: the coarse subset's size must be >= 0 (0: all at once; -1: automatic)");
  if (o.max_iterations < -1) throw Error("optimize_latent: the iteration limit must be >= 0 (-1: automatic)");
  const OptimizeOptions r = o.resolved(X0.rows());
  // The Gram's factor once for every evaluator of the placement (its scale search, its starts).
  const LikelihoodProblem shared = with_factor(p);
  if (r.coarse > 0 && r.coarse < X0.rows()) return coarse_to_fine(shared, X0, r, sink);
  return optimize_all_at_once(shared, X0, r, sink);
}

OptimizeOptions OptimizeOptions::resolved(Eigen::Index n) const {
  OptimizeOptions r = *this;
  const bool large = n >= kLargePlacement;
  if (r.coarse == -1) r.coarse = large ? static_cast<int>(std::lround(0.3 * static_cast<double>(n))) : 0;
  if (r.max_iterations == -1) {
    const double cube = static_cast<double>(n) * static_cast<double>(n) * static_cast<double>(n);
    r.max_iterations = large ? static_cast<int>(std::clamp(std::lround(1e11 / cube), 100L, 5000L)) : 5000;
  }
  return r;
}

const char* to_string(Optimizer method) {
  switch (method) {
    case Optimizer::lbfgs: return "lbfgs";
    case Optimizer::hooke_jeeves: return "hooke-jeeves";
  }
  return "unknown";
}

Optimizer optimizer_from_string(const std::string& name) {
  if (name == "lbfgs" || name == "l-bfgs") return Optimizer::lbfgs;
  if (name == "hooke-jeeves" || name == "hooke_jeeves" || name == "hj") return Optimizer::hooke_jeeves;
  throw Error("unknown optimizer '" + name + "' (choose lbfgs or hooke-jeeves)");
}

}  // namespace matlas::gp
