#include "manifold/project.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>


#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "gp/kernel.h"
#include "gp/minimize.h"

namespace matlas {

namespace {

/// Sums f(v, column, z, out) over the kept, measured values of the table into per-thread n-vectors.
template <class F>
Eigen::VectorXd sum_over_values(const Model& model, const BrdfTable& table, double* norm2,
                                std::size_t* missing, F f) {
  const int n = model.count();
  const std::size_t bins = table.bins(), total = table.size();
  const unsigned workers = worker_count();
  std::vector<Eigen::VectorXd> partial(workers, Eigen::VectorXd::Zero(n));
  std::vector<double> partial_norm(workers, 0.0);
  std::vector<std::size_t> partial_missing(workers, 0);
  parallel_for(0, workers, [&](std::size_t lo, std::size_t hi) {
    std::vector<float> row(static_cast<std::size_t>(n));
    for (std::size_t t = lo; t < hi; ++t) {
      for (std::size_t v = total * t / workers; v < total * (t + 1) / workers; ++v) {
        const int c = model.column_of(v);
        if (c < 0) continue;
        const auto channel = static_cast<int>(v / bins);
        if (!table.measured(channel, v % bins)) {
          ++partial_missing[t];
          continue;
        }
        const double z = table.value(channel, v % bins);
        partial_norm[t] += z * z;
        const float* data = model.data_f32(static_cast<std::size_t>(c));
        if (!data) {
          model.data(static_cast<std::size_t>(c), row.data());
          data = row.data();
        }
        f(static_cast<std::size_t>(c), z, data, partial[t]);
      }
    }
  });
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
  if (norm2) *norm2 = 0;
  if (missing) *missing = 0;
  for (unsigned t = 0; t < workers; ++t) {
    sum += partial[t];
    if (norm2) *norm2 += partial_norm[t];
    if (missing) *missing += partial_missing[t];
  }
  return sum;
}

}  // namespace

std::vector<int> nearest_materials(const Eigen::Ref<const Eigen::VectorXd>& distance2, int count) {
  std::vector<int> order(static_cast<std::size_t>(distance2.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return distance2[a] < distance2[b]; });
  order.resize(static_cast<std::size_t>(std::clamp(count, 0, static_cast<int>(order.size()))));
  return order;
}

MaterialInnerProducts inner_products(const Model& model, const BrdfTable& table) {
  if (table.dims() != model.dims())
    throw Error("material grid " + table.dims().to_string() + " differs from the model's " +
                model.dims().to_string());
  const int n = model.count();
  MaterialInnerProducts ip;
  ip.distance2 = sum_over_values(model, table, &ip.norm2, &ip.missing,
                                 [n](std::size_t, double z, const float* data, Eigen::VectorXd& out) {
                                   for (int i = 0; i < n; ++i) {
                                     const double d = z - static_cast<double>(data[i]);
                                     out[i] += d * d;
                                   }
                                 });
  ip.distance2.minCoeff(&ip.anchor);
  const int j = ip.anchor;
  ip.g = sum_over_values(model, table, nullptr, nullptr,
                         [&](std::size_t c, double z, const float* data, Eigen::VectorXd& out) {
                           const double diff = z - static_cast<double>(data[j]);
                           const double mean = model.mean(c);
                           for (int i = 0; i < n; ++i) out[i] += diff * (static_cast<double>(data[i]) - mean);
                         });
  return ip;
}

double projection_residual(const Model& model, const MaterialInnerProducts& ip, const Eigen::VectorXd& x,
                           Eigen::VectorXd* gradient, Model::WarmStart* warm) {
  const Eigen::MatrixXd& s = model.gram();
  MATLAS_CHECK(ip.distance2.size() == model.count() && ip.g.size() == model.count(), "inner products of this model");
  MATLAS_CHECK(ip.anchor >= 0 && ip.anchor < model.count(), "the anchor is a material");
  Eigen::VectorXd u = warm ? model.weights(x, *warm) : model.weights(x);
  u[ip.anchor] -= 1.0;
  const Eigen::VectorXd su = s * u;
  const double r = ip.distance2[ip.anchor] - 2.0 * u.dot(ip.g) + u.dot(su);
  if (gradient && model.interpolation() == Interpolation::convex) {
    // The convex weights are a projection of the GP's (piecewise smooth in x): central differences.
    gradient->resize(x.size());
    for (Eigen::Index d = 0; d < x.size(); ++d) {
      const double h = 1e-6 * std::max(1.0, std::abs(x[d]));
      Eigen::VectorXd xp = x, xm = x;
      xp[d] += h;
      xm[d] -= h;
      (*gradient)[d] =
          (projection_residual(model, ip, xp, nullptr, warm) - projection_residual(model, ip, xm, nullptr, warm)) / (2 * h);
    }
  } else if (gradient) {
    // dr/dx = sum_i g_i dk_i/dx with g = K^-1 (2 S u - 2 g), dk_i/dx = -2 (x - x_i) k_i / l^2.
    const gp::GpPosterior& post = model.posterior();
    const Eigen::VectorXd g = post.cholesky().solve(2.0 * (su - ip.g));
    const Eigen::MatrixXd& xs = model.latent();
    const double l2 = post.kernel().lengthscale * post.kernel().lengthscale;
    gradient->setZero(x.size());
    for (int i = 0; i < model.count(); ++i) {
      const Eigen::VectorXd diff = x - xs.row(i).transpose();
      const double k = std::exp(-diff.squaredNorm() / l2);
      *gradient += g[i] * (-2.0 / l2) * k * diff;
    }
  }
  return r;
}

Projection project_material(const Model& model, const BrdfTable& table, int starts) {
  const MaterialInnerProducts ip = inner_products(model, table);
  const int n = model.count();
  if (ip.missing >= model.kept_columns())
    throw Error("the material has no measured value in any of the model's " +
                std::to_string(model.kept_columns()) + " kept columns: nothing to project");
  if (!std::isfinite(ip.norm2) || !ip.distance2.allFinite() || !ip.g.allFinite())
    throw Error("the material's values overflow the distance computations (non-finite sums): it holds absurd values");
  if (ip.norm2 == 0.0) throw Error("every measured value of the material is zero: nothing to project");
  Projection p;
  p.missing = ip.missing;
  // Nearest materials in data space.
  const std::vector<int> order = nearest_materials(ip.distance2, std::max(starts, 1));
  MATLAS_CHECK(!order.empty(), "a model has at least one material");
  p.nearest = order[0];
  const double norm2 = std::max(ip.norm2, 1e-300);
  p.nearest_relative_error = std::sqrt(ip.distance2[p.nearest] / norm2);

  std::vector<Eigen::VectorXd> seeds;
  for (int k = 0; k < std::min(starts, n); ++k) seeds.push_back(model.latent().row(order[static_cast<std::size_t>(k)]).transpose());
  seeds.push_back(model.latent().colwise().mean().transpose());

  gp::MinimizeOptions search;  // L-BFGS: 200 iterations, |grad| <= 1e-8 max(1, |x|)
  search.max_iterations = 200;
  search.gradient_tolerance = search.relative_gradient_tolerance = 1e-8;
  const double scale = 1.0 / norm2;  // keep the objective O(1)
  Model::WarmStart warm;  // one search's points are near each other
  auto objective = [&](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    const double r = projection_residual(model, ip, x, &grad, &warm);
    grad *= scale;
    return r * scale;
  };
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::VectorXd& seed : seeds) {
    // The seed itself: at a material's own point the GP reproduces it exactly (w = e_i), a value
    // the smooth search near it does not see.
    const double at_seed = projection_residual(model, ip, seed) * scale;
    if (at_seed < best) {
      best = at_seed;
      p.x = seed;
    }
  }
  for (Eigen::VectorXd x : seeds) {
    warm = Model::WarmStart();
    double fx = 0;
    if (const std::optional<double> end = gp::minimize_lbfgs(objective, x, search)) {
      fx = *end;
    } else {
      // A failed line search leaves x at its last point, which may have left the finite range
      // (a step into a flat region): keep it only if it is a usable point.
      if (!x.allFinite()) continue;
      Eigen::VectorXd g;
      fx = objective(x, g);
    }
    if (fx < best && x.allFinite()) {
      best = fx;
      p.x = x;
    }
  }
  p.residual2 = std::max(0.0, projection_residual(model, ip, p.x));
  p.relative_error = std::sqrt(p.residual2 / norm2);
  p.variance = model.variance(p.x);
  if (!p.x.allFinite() || !std::isfinite(p.relative_error) || !std::isfinite(p.variance))
    throw Error("the projection did not give a finite point (non-finite arithmetic): the material's values are unusable");
  return p;
}

}  // namespace matlas
