#include "eval/latent_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "eval/gram_space.h"
#include "gp/initialize.h"
#include "gp/minimize.h"
#include "manifold/project.h"

namespace matlas::eval {

LatentFit fit_latent(const Eigen::MatrixXd& centred_gram, double columns, int q,
                     const FitOptions& options) {
  gp::LikelihoodProblem problem;
  problem.gram = centred_gram;
  problem.columns = columns;
  problem.kernel.nugget = options.nugget;
  problem.prior = options.prior;
  const gp::OptimizeResult result =
      place_latent_points(problem, q, BuildOptions::resolved(options.optimize, q), options.sparse);
  LatentFit fit;
  fit.posterior = std::make_shared<const gp::GpPosterior>(result.latent, problem.kernel);
  fit.log_likelihood = result.value;
  if (options.convex_ridge > 0) fit.convex = std::make_shared<const gp::ConvexProjection>(centred_gram, options.convex_ridge);
  return fit;
}

GramProjection project_in_gram(const LatentFit& fit, std::span<const int> subset,
                               const Eigen::MatrixXd& gram, int h, int starts) {
  const Eigen::MatrixXd& X = fit.latent();
  if (X.rows() != static_cast<Eigen::Index>(subset.size()))
    throw Error("projection: the fit has " + std::to_string(X.rows()) + " points for a subset of " +
                std::to_string(subset.size()));
  const int n = static_cast<int>(gram.rows());
  auto coefficients = [&](const Eigen::VectorXd& x) {
    return raw_from_weights(fit.weights(x), subset, n);
  };
  // The optimiser's points are close to one another: each convex solve starts from the last.
  gp::ConvexProjection::WarmStart warm;
  auto objective = [&](const Eigen::VectorXd& x) {
    return residual_squared(gram, raw_from_weights(fit.weights(x, warm), subset, n), h);
  };

  // Starting points: the latent points of the materials nearest to h in this Gram.
  Eigen::VectorXd distance2(static_cast<Eigen::Index>(subset.size()));
  for (std::size_t k = 0; k < subset.size(); ++k) {
    const int i = subset[k];
    distance2[static_cast<Eigen::Index>(k)] = gram(i, i) + gram(h, h) - 2.0 * gram(i, h);
  }
  const std::vector<int> near = nearest_materials(distance2, std::max(starts, 1));
  const double rms = std::sqrt(X.rowwise().squaredNorm().mean() + 1e-300);
  const double step = 0.1 * std::max(rms, 1e-6);
  GramProjection best;
  best.residual_squared = std::numeric_limits<double>::infinity();
  for (const int k : near) {
    const Eigen::VectorXd x0 = X.row(k).transpose();
    const Eigen::VectorXd x = gp::minimize_nelder_mead(
        objective, x0, gp::MinimizeOptions::nelder_mead(step, 200 * static_cast<int>(X.cols() + 1)));
    for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0}) best.candidates.push_back(coefficients(x0 + t * (x - x0)));
    const double r = objective(x);
    if (r < best.residual_squared) {
      best.x = x;
      best.residual_squared = r;
    }
  }
  best.coefficients = coefficients(best.x);
  return best;
}

}  // namespace matlas::eval
