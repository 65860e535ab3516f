#include "gp/optimize.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/error.h"
#include "gp/optimize_methods.h"

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

}  // namespace

OptimizeResult optimize_latent(const LikelihoodProblem& p, Eigen::MatrixXd X0, const OptimizeOptions& o,
                               ProgressSink& sink) {
  if (!X0.allFinite()) throw Error("optimize_latent: the initial latent points contain NaN or infinity");
  if (o.starts < 1) throw Error("optimize_latent: starts must be >= 1 (got " + std::to_string(o.starts) + ")");
  if (o.starts == 1) return optimize_one(p, X0, o, sink);

  const auto begin = std::chrono::steady_clock::now();
  const Eigen::RowVectorXd centroid = X0.colwise().mean();
  OptimizeResult best;
  int iterations = 0, evaluations = 0;
  for (int k = 0; k < o.starts; ++k) {
    OptimizeOptions one = o;
    if (o.time_limit_seconds > 0) {
      const double used = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      if (k > 0 && used >= o.time_limit_seconds) break;
      one.time_limit_seconds = std::max(o.time_limit_seconds - used, 1e-9);
    }
    const double scale = start_scale(k);
    sink.message("start " + std::to_string(k + 1) + "/" + std::to_string(o.starts) + " (X0 scaled by " +
                 std::to_string(scale) + ")");
    const Eigen::MatrixXd start = (scale * (X0.rowwise() - centroid)).rowwise() + centroid;
    OptimizeResult r = optimize_one(p, start, one, sink);
    iterations += r.iterations;
    evaluations += r.evaluations;
    const bool done = r.stop_reason == "target value reached" || r.stop_reason == "time limit reached";
    if (k == 0 || r.value > best.value) {
      best = std::move(r);
      best.best_start = k;
    }
    if (done) break;
  }
  best.iterations = iterations;
  best.evaluations = evaluations;
  best.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  best.stop_reason += " (best of " + std::to_string(o.starts) + " starts: start " + std::to_string(best.best_start + 1) + ")";
  return best;
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
