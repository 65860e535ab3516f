#include "acquisition/sparse_fit.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/check.h"
#include "core/error.h"
#include "gp/convex_weights.h"
#include "gp/minimize.h"

namespace matlas::acquisition {

void SampleRows::add(int sample_index, const Eigen::Ref<const Eigen::MatrixXd>& values, const Eigen::Array3d& y,
                     const Eigen::Array3d& s, double cosine_factor) {
  MATLAS_CHECK_EQ(values.rows(), Eigen::Index{3});
  const Eigen::Index r = rows(), n = values.cols();
  MATLAS_CHECK(r == 0 || inputs.cols() == n, "the rows so far have another number of inputs");
  inputs.conservativeResize(r + 3, n);
  measured.conservativeResize(r + 3);
  sigma.conservativeResize(r + 3);
  cosine.conservativeResize(r + 3);
  for (int c = 0; c < 3; ++c) {
    inputs.row(r + c) = values.row(c);
    measured(r + c) = y(c);
    sigma(r + c) = s(c);
    cosine(r + c) = cosine_factor;
    sample.push_back(sample_index);
    channel.push_back(c);
  }
}

double transform_value(const LayoutTransform& transform, double f, double c) {
  double g = f;
  switch (transform.map) {
    case LayoutTransform::Map::linear: break;
    case LayoutTransform::Map::cube_root: g = std::cbrt(f); break;
    case LayoutTransform::Map::log: g = std::copysign(std::log1p(100.0 * std::abs(f)), f); break;
  }
  return transform.cosine_weighted ? g * c : g;
}

namespace {

/// The Cauchy loss's constant: 95 % efficiency on Gaussian residuals.
constexpr double kCauchy = 2.385;

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

/// The objective of one fit: transformed measurements and row scales fixed, x varying.
struct Objective {
  const MapView& map;
  const SampleRows& rows;
  const SparseFitOptions& options;
  Eigen::VectorXd target;   // t(measured)
  Eigen::VectorXd scale;    // s per row
  mutable int evaluations = 0;

  Eigen::VectorXd transformed(const Eigen::VectorXd& predicted) const {
    Eigen::VectorXd t(predicted.size());
    for (Eigen::Index r = 0; r < t.size(); ++r) t(r) = transform_value(options.transform, predicted(r), rows.cosine(r));
    return t;
  }
  double loss_of_residual(const Eigen::VectorXd& residual) const {
    double sum = 0;
    for (Eigen::Index r = 0; r < residual.size(); ++r) {
      const double u = residual(r) / scale(r);
      sum += options.robust ? std::log1p(u * u / (kCauchy * kCauchy)) : u * u;
    }
    return sum;
  }
  double loss_of_prediction(const Eigen::VectorXd& predicted) const {
    return loss_of_residual(transformed(predicted) - target);
  }
  double operator()(const Eigen::VectorXd& x) const {
    ++evaluations;
    return loss_of_prediction(rows.inputs * map.coefficients(x));
  }
  /// The loss of the rows where `mask` is set.
  double loss_on(const Eigen::VectorXd& predicted, const std::vector<bool>& mask) const {
    double sum = 0;
    for (Eigen::Index r = 0; r < predicted.size(); ++r) {
      if (!mask[static_cast<std::size_t>(r)]) continue;
      const double u = (transform_value(options.transform, predicted(r), rows.cosine(r)) - target(r)) / scale(r);
      sum += options.robust ? std::log1p(u * u / (kCauchy * kCauchy)) : u * u;
    }
    return sum;
  }
  /// dt/df at f for row r (cube root: bounded near 0 by `floor`).
  double slope(double f, Eigen::Index r, double floor) const {
    const double c = options.transform.cosine_weighted ? rows.cosine(r) : 1.0;
    switch (options.transform.map) {
      case LayoutTransform::Map::linear: return c;
      case LayoutTransform::Map::cube_root: {
        const double a = std::max(std::abs(f), floor);
        return c / (3.0 * std::cbrt(a * a));
      }
      case LayoutTransform::Map::log: return c * 100.0 / (1.0 + 100.0 * std::abs(f));
    }
    return c;
  }
};

/// The combination stage on the rows in `mask`: Gauss-Newton with the loss's weights on
/// loss(c) + lambda (c - anchor)^T A (c - anchor) over the simplex, from `anchor`.
struct CombinationFit {
  const Objective& objective;
  const Eigen::MatrixXd& A;
  double floor;  // of the cube root's slope

  double total(const Eigen::VectorXd& c, const Eigen::VectorXd& anchor, double lambda, const std::vector<bool>& mask) const {
    const Eigen::VectorXd d = c - anchor;
    return objective.loss_on(objective.rows.inputs * c, mask) + lambda * d.dot(A * d);
  }
  /// The Gauss-Newton curvature of the loss at c over the rows in mask (n x n), and the matching
  /// right-hand side for the step's quadratic programme.
  void linearise(const Eigen::VectorXd& c, const std::vector<bool>& mask, Eigen::MatrixXd& H, Eigen::VectorXd& rhs) const {
    const SampleRows& rows = objective.rows;
    const Eigen::VectorXd predicted = rows.inputs * c;
    const Eigen::Index n = c.size();
    Eigen::MatrixXd J(rows.rows(), n);
    Eigen::VectorXd b(rows.rows()), omega(rows.rows());
    for (Eigen::Index r = 0; r < rows.rows(); ++r) {
      if (!mask[static_cast<std::size_t>(r)]) {
        J.row(r).setZero();
        b(r) = 0;
        omega(r) = 0;
        continue;
      }
      const double s = objective.scale(r);
      const double u = (transform_value(objective.options.transform, predicted(r), rows.cosine(r)) - objective.target(r)) / s;
      J.row(r) = rows.inputs.row(r) * (objective.slope(predicted(r), r, floor) / s);
      b(r) = J.row(r).dot(c) - u;  // u(c') ~ J c' - b
      // Cauchy: the IRLS weight of log(1 + u^2 / k^2) is 1 / (k^2 + u^2); least squares: 1.
      omega(r) = objective.options.robust ? 1.0 / (kCauchy * kCauchy + u * u) : 1.0;
    }
    H = J.transpose() * omega.asDiagonal() * J;
    rhs = J.transpose() * omega.cwiseProduct(b);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& anchor, double lambda, const std::vector<bool>& mask, int iterations = 6) const {
    Eigen::VectorXd c = anchor;
    double value = total(c, anchor, lambda, mask);
    const Eigen::Index n = c.size();
    for (int it = 0; it < iterations; ++it) {
      Eigen::MatrixXd H;
      Eigen::VectorXd rhs;
      linearise(c, mask, H, rhs);
      H += lambda * A;
      rhs += lambda * (A * anchor);
      // The minimiser of the step's quadratic on the plane sum c = 1, then its projection onto
      // the simplex in H's metric (the same minimiser over the simplex).
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
      const Eigen::VectorXd g = ldlt.solve(rhs), h1 = ldlt.solve(Eigen::VectorXd::Ones(n));
      const Eigen::VectorXd on_plane = g + h1 * ((1.0 - g.sum()) / h1.sum());
      if (!on_plane.allFinite()) break;
      const Eigen::VectorXd proposal = gp::ConvexProjection(H, 1e-12).project(on_plane);
      double step = 1;
      bool moved = false;
      for (int k = 0; k < 6; ++k, step *= 0.5) {
        const Eigen::VectorXd next = c + step * (proposal - c);
        const double v = total(next, anchor, lambda, mask);
        if (v < value) {
          moved = (next - c).lpNorm<1>() > 1e-9;
          c = next;
          value = v;
          break;
        }
      }
      if (!moved) break;
    }
    return c;
  }
  /// lambda for a relative strength gamma: gamma times the loss's curvature over A's, at c.
  double lambda_of(double gamma, const Eigen::VectorXd& c, const std::vector<bool>& mask) const {
    Eigen::MatrixXd H;
    Eigen::VectorXd rhs;
    linearise(c, mask, H, rhs);
    return gamma * H.trace() / std::max(A.trace(), 1e-300);
  }
};

/// Nelder-Mead from the latent points of the inputs that explain the rows best alone, and from
/// the centroid and `extra` points. Returns the best point.
Eigen::VectorXd search(const Objective& objective, const std::vector<Eigen::VectorXd>& extra, double step, int starts,
                       int evaluations) {
  const Eigen::MatrixXd& X = objective.map.latent;
  const Eigen::Index n = X.rows();
  std::vector<double> alone(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    alone[static_cast<std::size_t>(i)] = objective.loss_of_prediction(objective.rows.inputs.col(i));
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return alone[static_cast<std::size_t>(a)] < alone[static_cast<std::size_t>(b)]; });
  std::vector<Eigen::VectorXd> points = extra;
  for (int k = 0; k < std::min<int>(starts, static_cast<int>(n)); ++k) points.push_back(X.row(order[static_cast<std::size_t>(k)]).transpose());
  points.push_back(X.colwise().mean().transpose());
  Eigen::VectorXd best;
  double best_loss = std::numeric_limits<double>::infinity();
  for (const auto& start : points) {
    const Eigen::VectorXd x =
        gp::minimize_nelder_mead(std::cref(objective), start, gp::MinimizeOptions::nelder_mead(step, evaluations, 1e-9));
    const double l = objective(x);
    if (l < best_loss) best_loss = l, best = x;
  }
  return best;
}

/// The combination stage's choice: 4-fold cross-validation over the samples of the strengths
/// gamma in {0.01, 0.1, 1} and infinity (the map point, refitted per fold from x by one local
/// search), then the winner on all samples.
void choose_combination(const Objective& objective, const MapView& map, const Eigen::VectorXd& x, double step,
                        int evaluations, double typical, int distinct, SparseFit& fit) {
  const SampleRows& rows = objective.rows;
  const Eigen::Index R = rows.rows();
  // Folds by sample: the samples' distinct ids in order, dealt round-robin.
  std::vector<int> ids = rows.sample;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  const int folds = std::min(4, distinct);
  auto fold_of = [&](Eigen::Index r) {
    return static_cast<int>(std::lower_bound(ids.begin(), ids.end(), rows.sample[static_cast<std::size_t>(r)]) - ids.begin()) % folds;
  };
  // The cube root's slope is bounded where a value is below 1e-3 of the typical magnitude
  // (in physical units: the typical transformed value undone roughly).
  const double floor = 1e-9 + 1e-3 * std::pow(typical, 3.0);
  const CombinationFit stage{objective, map.metric, floor};
  const std::vector<double> gammas{0.01, 0.1, 1};
  std::vector<double> held_out(gammas.size() + 1, 0.0);  // the last: the map point
  for (int f = 0; f < folds; ++f) {
    std::vector<bool> train(static_cast<std::size_t>(R)), test(static_cast<std::size_t>(R));
    for (Eigen::Index r = 0; r < R; ++r) (fold_of(r) == f ? test : train)[static_cast<std::size_t>(r)] = true;
    auto train_loss = [&](const Eigen::VectorXd& p) { return objective.loss_on(rows.inputs * map.coefficients(p), train); };
    const Eigen::VectorXd xf =
        gp::minimize_nelder_mead(train_loss, x, gp::MinimizeOptions::nelder_mead(step, evaluations / 3, 1e-9));
    const Eigen::VectorXd anchor = map.coefficients(xf);
    held_out.back() += objective.loss_on(rows.inputs * anchor, test);
    for (std::size_t g = 0; g < gammas.size(); ++g) {
      const Eigen::VectorXd c = stage.solve(anchor, stage.lambda_of(gammas[g], anchor, train), train);
      held_out[g] += objective.loss_on(rows.inputs * c, test);
    }
  }
  const auto best = static_cast<std::size_t>(std::min_element(held_out.begin(), held_out.end()) - held_out.begin());
  if (best == gammas.size()) return;  // the map point predicts held-out samples best
  const std::vector<bool> all(static_cast<std::size_t>(R), true);
  fit.coefficients = stage.solve(fit.map_coefficients, stage.lambda_of(gammas[best], fit.map_coefficients, all), all);
  fit.combination_strength = gammas[best];
  fit.combined = true;
}

/// How many distinct samples the rows come from.
int distinct_samples(std::vector<int> sample) {
  std::sort(sample.begin(), sample.end());
  return static_cast<int>(std::unique(sample.begin(), sample.end()) - sample.begin());
}

/// Rows with a given uncertainty sigma get it carried into the transform's space as their scale
/// (half the spread of t(y +- sigma), at least 1e-9 of the `typical` magnitude); returns which
/// rows have one (the others get the robust scale).
std::vector<bool> scale_known_rows(Objective& objective, const SampleRows& rows, const LayoutTransform& transform,
                                   double typical) {
  const Eigen::Index R = rows.rows();
  std::vector<bool> known(static_cast<std::size_t>(R));
  for (Eigen::Index r = 0; r < R; ++r) {
    const double s = rows.sigma(r), y = rows.measured(r), c = rows.cosine(r);
    known[static_cast<std::size_t>(r)] = s > 0;
    if (s > 0)
      objective.scale(r) = std::max(0.5 * std::abs(transform_value(transform, y + s, c) -
                                                   transform_value(transform, y - s, c)),
                                    1e-9 * typical);
  }
  return known;
}

/// Outliers: samples all of whose rows weigh less than 0.1.
std::vector<int> outlier_samples(const std::vector<int>& sample, const Eigen::VectorXd& weight, int samples) {
  MATLAS_CHECK_EQ(sample.size(), static_cast<std::size_t>(weight.size()));
  std::vector<double> heaviest(static_cast<std::size_t>(samples), 0.0);
  for (Eigen::Index r = 0; r < weight.size(); ++r) {
    MATLAS_DCHECK(sample[static_cast<std::size_t>(r)] >= 0 && sample[static_cast<std::size_t>(r)] < samples,
                  "a row's sample index");
    auto& h = heaviest[static_cast<std::size_t>(sample[static_cast<std::size_t>(r)])];
    h = std::max(h, weight(r));
  }
  std::vector<int> outliers;
  for (int s = 0; s < samples; ++s)
    if (std::count(sample.begin(), sample.end(), s) > 0 && heaviest[static_cast<std::size_t>(s)] < 0.1)
      outliers.push_back(s);
  return outliers;
}

/// The covariance of the fitted point fit.x: Gauss-Newton on the weighted, scaled residuals
/// (central differences of step h), times their spread; directions the samples do not constrain
/// get a large variance.
Eigen::MatrixXd latent_covariance(const Objective& objective, const MapView& map, const SampleRows& rows,
                                  const SparseFit& fit, double h) {
  const Eigen::Index R = rows.rows(), q = fit.x.size();
  Eigen::MatrixXd J(R, q);
  for (Eigen::Index d = 0; d < q; ++d) {
    Eigen::VectorXd a = fit.x, b = fit.x;
    a(d) += h;
    b(d) -= h;
    J.col(d) = (objective.transformed(rows.inputs * map.coefficients(a)) -
                objective.transformed(rows.inputs * map.coefficients(b))) / (2 * h);
  }
  for (Eigen::Index r = 0; r < R; ++r) J.row(r) *= std::sqrt(fit.weight(r)) / objective.scale(r);
  double spread = 0;
  for (Eigen::Index r = 0; r < R; ++r) {
    const double u = fit.residual(r) / objective.scale(r);
    spread += fit.weight(r) * u * u;
  }
  spread /= static_cast<double>(std::max<Eigen::Index>(R - q, 1));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(J.transpose() * J);
  const Eigen::VectorXd lambda = eigen.eigenvalues();
  const double floor = std::max(lambda.maxCoeff(), 1e-300) * 1e-12;
  const Eigen::VectorXd inverse = lambda.unaryExpr([&](double l) { return 1.0 / std::max(l, floor); });
  return spread * eigen.eigenvectors() * inverse.asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace

SparseFit fit_rows(const MapView& map, const SampleRows& rows, const SparseFitOptions& options) {
  const Eigen::Index n = map.latent.rows(), q = map.latent.cols(), R = rows.rows();
  if (!map.coefficients) throw Error("sparse fit: the map has no coefficient function");
  if (rows.inputs.rows() != R || rows.inputs.cols() != n || rows.sigma.size() != R || rows.cosine.size() != R)
    throw Error("sparse fit: the sample rows (" + std::to_string(rows.inputs.rows()) + " x " +
                std::to_string(rows.inputs.cols()) + ") do not match the map's " + std::to_string(n) + " inputs");
  MATLAS_CHECK_EQ(rows.sample.size(), static_cast<std::size_t>(R));  // SampleRows::add keeps them together
  const int samples = R == 0 ? 0 : 1 + *std::max_element(rows.sample.begin(), rows.sample.end());
  const int distinct = distinct_samples(rows.sample);
  if (distinct < q + 1)
    throw Error(std::to_string(distinct) + " measured sample" + (distinct == 1 ? "" : "s") +
                " cannot place a point on a map of dimension " + std::to_string(q) + ": at least " +
                std::to_string(q + 1) + " are needed (and 10 or more give a reliable fit)");

  Objective objective{map, rows, options, {}, Eigen::VectorXd::Ones(R)};
  objective.target = objective.transformed(rows.measured);
  // Row scales: a given uncertainty carried into the transform's space (half the spread of
  // t(y +- sigma)), else the robust scale tau, first a guess, then from a first fit's residuals.
  std::vector<double> magnitudes;
  for (Eigen::Index r = 0; r < R; ++r) magnitudes.push_back(std::abs(objective.target(r)));
  const double typical = std::max(median_of(magnitudes), 1e-12);
  const std::vector<bool> known = scale_known_rows(objective, rows, options.transform, typical);
  const bool any_unknown = std::find(known.begin(), known.end(), false) != known.end();
  auto set_tau = [&](double tau) {
    for (Eigen::Index r = 0; r < R; ++r)
      if (!known[static_cast<std::size_t>(r)]) objective.scale(r) = tau;
  };

  double extent = 0;
  for (Eigen::Index d = 0; d < q; ++d) extent += map.latent.col(d).maxCoeff() - map.latent.col(d).minCoeff();
  extent = std::max(extent / static_cast<double>(q), 1e-3);
  const double step = 0.05 * extent;
  const int evaluations = options.evaluations > 0 ? options.evaluations : 150 * static_cast<int>(q + 1);

  // A coarse search from every start, then (with the robust scale found) a fine one from where
  // it ended.
  double tau = 0.05 * typical;
  set_tau(tau);
  Eigen::VectorXd x = search(objective, {}, step, options.starts, evaluations / 3);
  x = gp::minimize_nelder_mead(std::cref(objective), x, gp::MinimizeOptions::nelder_mead(step, evaluations, 1e-9));
  if (any_unknown) {
    const Eigen::VectorXd residual = objective.transformed(rows.inputs * map.coefficients(x)) - objective.target;
    std::vector<double> absolute;
    for (Eigen::Index r = 0; r < R; ++r)
      if (!known[static_cast<std::size_t>(r)]) absolute.push_back(std::abs(residual(r)));
    tau = std::max({1.4826 * median_of(absolute), 1e-3 * typical, 1e-12});
    set_tau(tau);
    x = gp::minimize_nelder_mead(std::cref(objective), x, gp::MinimizeOptions::nelder_mead(step, evaluations, 1e-9));
  }

  SparseFit fit;
  fit.x = x;
  fit.map_coefficients = map.coefficients(x);
  MATLAS_CHECK_EQ(fit.map_coefficients.size(), n);  // the map's coefficient function: one per input
  fit.coefficients = fit.map_coefficients;
  fit.combination_strength = std::numeric_limits<double>::infinity();
  if (options.combination && map.metric.rows() == n && distinct >= 4)
    choose_combination(objective, map, x, step, evaluations, typical, distinct, fit);
  fit.predicted = rows.inputs * fit.coefficients;
  fit.residual = objective.transformed(fit.predicted) - objective.target;
  fit.loss = objective.loss_of_residual(fit.residual);
  fit.scale = any_unknown ? tau : 0;
  fit.variance = map.variance ? map.variance(x) : 0;
  fit.weight.resize(R);
  for (Eigen::Index r = 0; r < R; ++r) {
    const double u = fit.residual(r) / objective.scale(r);
    fit.weight(r) = options.robust ? 1.0 / (1.0 + u * u / (kCauchy * kCauchy)) : 1.0;
  }
  fit.input_loss.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) fit.input_loss(i) = objective.loss_of_prediction(rows.inputs.col(i));
  fit.input_loss.minCoeff(&fit.best_input);
  fit.outliers = outlier_samples(rows.sample, fit.weight, samples);

  fit.latent_covariance = latent_covariance(objective, map, rows, fit, 1e-4 * extent);
  MATLAS_CHECK(fit.latent_covariance.rows() == q && fit.latent_covariance.cols() == q, "a q x q covariance");
  fit.evaluations = objective.evaluations;
  return fit;
}

}  // namespace matlas::acquisition
