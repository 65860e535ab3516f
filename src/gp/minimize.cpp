#include "gp/minimize.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <numeric>
#include <vector>

#include "gp/lbfgs_driver.h"

namespace matlas::gp {

std::optional<double> minimize_lbfgs(const ObjectiveWithGradient& f, Eigen::VectorXd& x, const MinimizeOptions& o) {
  // The solver keeps a reference to its parameters: they must outlive it (a temporary here was a
  // stack use after scope, found by fuzz_api through POST /api/project).
  const LBFGSpp::LBFGSParam<double> param = detail::lbfgs_param(o);
  LBFGSpp::LBFGSSolver<double> solver(param);
  double fx = 0;
  try {
    solver.minimize(f, x, fx);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return fx;
}

Eigen::VectorXd minimize_nelder_mead(const std::function<double(const Eigen::VectorXd&)>& f, Eigen::VectorXd x0,
                                     const MinimizeOptions& o) {
  const double step = o.step, tolerance = o.value_tolerance;
  const int max_evaluations = o.max_iterations;
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

}  // namespace matlas::gp
