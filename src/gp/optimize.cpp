#include "gp/optimize.h"

#include "core/error.h"
#include "gp/optimize_methods.h"

namespace matlas::gp {

OptimizeResult optimize_latent(const LikelihoodProblem& p, Eigen::MatrixXd X0, const OptimizeOptions& o,
                               ProgressSink& sink) {
  if (!X0.allFinite()) throw Error("optimize_latent: the initial latent points contain NaN or infinity");
  detail::OptimizationRun run(p, X0, o, sink);
  if (o.max_iterations == 0) return run.finish("iteration limit reached");
  switch (o.method) {
    case Optimizer::lbfgs: return run.finish(detail::run_lbfgs(run));
    case Optimizer::hooke_jeeves: return run.finish(detail::run_hooke_jeeves(run));
  }
  throw Error("optimize_latent: unknown optimizer");
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
