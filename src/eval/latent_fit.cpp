#include "eval/latent_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "eval/gram_space.h"
#include "gp/initialize.h"
#include "manifold/project.h"

namespace matlas::eval {

LatentFit fit_latent(const Eigen::MatrixXd& centred_gram, double columns, int q,
                     const FitOptions& options) {
  gp::LikelihoodProblem problem;
  problem.gram = centred_gram;
  problem.columns = columns;
  problem.kernel.nugget = options.nugget;
  problem.prior = options.prior;
  const Eigen::MatrixXd X0 = gp::pca_initialization(problem, q);
  const gp::OptimizeResult result =
      gp::optimize_latent(problem, X0, BuildOptions::resolved(options.optimize, q), null_progress());
  LatentFit fit;
  fit.posterior = std::make_shared<const gp::GpPosterior>(result.latent, problem.kernel);
  fit.log_likelihood = result.value;
  if (options.convex_ridge > 0) fit.convex = std::make_shared<const gp::ConvexProjection>(centred_gram, options.convex_ridge);
  return fit;
}

Eigen::VectorXd nelder_mead(const std::function<double(const Eigen::VectorXd&)>& f,
                            Eigen::VectorXd x0, double step, int max_evaluations,
                            double tolerance) {
  const auto d = x0.size();
  std::vector<Eigen::VectorXd> pts(static_cast<std::size_t>(d + 1), x0);
  std::vector<double> val(pts.size());
  for (Eigen::Index k = 0; k < d; ++k) pts[static_cast<std::size_t>(k + 1)](k) += step;
  int evals = 0;
  for (std::size_t k = 0; k < pts.size(); ++k, ++evals) val[k] = f(pts[k]);
  std::vector<std::size_t> order(pts.size());
  while (evals < max_evaluations) {
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return val[a] < val[b]; });
    const std::size_t best = order.front(), worst = order.back(), second = order[order.size() - 2];
    double extent = 0;
    for (const auto& p : pts) extent = std::max(extent, (p - pts[best]).cwiseAbs().maxCoeff());
    if (val[worst] - val[best] <= tolerance * (std::abs(val[best]) + 1e-300) && extent < 1e-9 * (1 + pts[best].norm()))
      break;
    if (extent < 1e-12 * (1 + pts[best].norm())) break;
    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(d);
    for (std::size_t k = 0; k < pts.size(); ++k)
      if (k != worst) centroid += pts[k];
    centroid /= static_cast<double>(d);
    const Eigen::VectorXd xr = centroid + (centroid - pts[worst]);
    const double fr = f(xr);
    ++evals;
    if (fr < val[best]) {
      const Eigen::VectorXd xe = centroid + 2.0 * (centroid - pts[worst]);
      const double fe = f(xe);
      ++evals;
      if (fe < fr) pts[worst] = xe, val[worst] = fe;
      else pts[worst] = xr, val[worst] = fr;
    } else if (fr < val[second]) {
      pts[worst] = xr, val[worst] = fr;
    } else {
      const bool outside = fr < val[worst];
      const Eigen::VectorXd xc = outside ? Eigen::VectorXd(centroid + 0.5 * (xr - centroid))
                                         : Eigen::VectorXd(centroid + 0.5 * (pts[worst] - centroid));
      const double fc = f(xc);
      ++evals;
      if (fc < (outside ? fr : val[worst])) {
        pts[worst] = xc, val[worst] = fc;
      } else {  // shrink towards the best point
        for (std::size_t k = 0; k < pts.size(); ++k) {
          if (k == best) continue;
          pts[k] = pts[best] + 0.5 * (pts[k] - pts[best]);
          val[k] = f(pts[k]);
          ++evals;
        }
      }
    }
  }
  const auto best = static_cast<std::size_t>(std::min_element(val.begin(), val.end()) - val.begin());
  return pts[best];
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
  auto objective = [&](const Eigen::VectorXd& x) { return residual_squared(gram, coefficients(x), h); };

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
    const Eigen::VectorXd x = nelder_mead(objective, x0, step, 200 * static_cast<int>(X.cols() + 1));
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
