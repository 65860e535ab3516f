#include "eval/manifold_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "brdf/merl_grid.h"
#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "eval/model_checks.h"
#include "eval/statistics.h"
#include "gp/kernel.h"
#include "manifold/dense_product.h"

namespace matlas::eval {

namespace {

Eigen::MatrixXd latent_squared_distances(const Eigen::MatrixXd& X) {
  Eigen::MatrixXd D;
  gp::squared_distances(X, D);
  return D;
}

/// Indices 0..n-1 except i, sorted by D(i, .) (ties by index).
std::vector<int> neighbours_by(const Eigen::MatrixXd& D, int i) {
  MATLAS_CHECK(D.rows() == D.cols() && i >= 0 && i < D.rows(), "a row of a square distance matrix");
  std::vector<int> order(static_cast<std::size_t>(D.rows()));
  std::iota(order.begin(), order.end(), 0);
  order.erase(order.begin() + i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return D(i, a) < D(i, b); });
  return order;
}

/// Squared cube-root distances between the inputs, sum over values of
/// (cbrt(c_b z_i) - cbrt(c_b z_j))^2 on every stride-th value (c_b: the bin's cosine factor).
Eigen::MatrixXd perceptual_squared_distances(const Model& model, int stride) {
  const int n = model.count();
  const std::vector<double> cosine = bin_cosine_factors(model.dims());
  const std::size_t bins = model.dims().bins();
  MATLAS_CHECK_EQ(cosine.size(), bins);
  std::vector<std::size_t> columns;
  for (std::size_t v = 0; v < 3 * bins; v += static_cast<std::size_t>(stride))
    if (model.kept(v) && cosine[v % bins] > 0) columns.push_back(v);
  Eigen::MatrixXd T(static_cast<Eigen::Index>(columns.size()), n);
  parallel_for(0, columns.size(), [&](std::size_t lo, std::size_t hi) {
    std::vector<float> values(static_cast<std::size_t>(n));
    for (std::size_t r = lo; r < hi; ++r) {
      const std::size_t v = columns[r];
      model.data(static_cast<std::size_t>(model.column_of(v)), values.data());
      for (int i = 0; i < n; ++i)
        T(static_cast<Eigen::Index>(r), i) = std::cbrt(cosine[v % bins] * static_cast<double>(values[static_cast<std::size_t>(i)]));
    }
  }, 4096);
  const Eigen::MatrixXd G = blas_product(T.transpose(), T);
  Eigen::MatrixXd D(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) D(i, j) = G(i, i) + G(j, j) - 2 * G(i, j);
  return D;
}

ModePlausibility summarise(const Model& model, const Eigen::MatrixXd& W, double inputs_max_albedo,
                           const std::vector<std::size_t>& input_negatives, double budget, std::string mode,
                           std::string where) {
  ModePlausibility p;
  p.mode = std::move(mode);
  p.where = std::move(where);
  p.points = static_cast<int>(W.cols());
  if (W.cols() == 0) return p;
  // Counted only where a negative value can be; past the budget on every s-th value.
  const NegativeCounts counts = count_possible_negatives(model, W, input_negatives, budget);
  const std::vector<std::size_t>& negatives = counts.negatives;
  p.value_stride = static_cast<int>(counts.stride);
  const Eigen::MatrixXd albedo = model.albedo_batch(W);
  const double kept = static_cast<double>(std::max<std::size_t>(counts.visited, 1));
  double sum = 0;
  for (std::size_t j = 0; j < negatives.size(); ++j) {
    const double share = static_cast<double>(negatives[j]) / kept;
    p.with_negative += negatives[j] > 0 ? 1 : 0;
    sum += share;
    p.worst_negative_share = std::max(p.worst_negative_share, share);
  }
  p.mean_negative_share = sum / static_cast<double>(negatives.size());
  p.worst_albedo_ratio = albedo.maxCoeff() / inputs_max_albedo;
  p.most_negative_weight = W.minCoeff();
  return p;
}

}  // namespace

double trustworthiness(const Eigen::MatrixXd& high, const Eigen::MatrixXd& latent, int k) {
  const auto n = static_cast<int>(latent.rows());
  if (high.rows() != n || high.cols() != n) throw Error("trustworthiness: distance matrix and points disagree");
  if (k < 1 || 2 * k >= n - 1) throw Error("trustworthiness: k must be in [1, (n - 2) / 2]");
  const Eigen::MatrixXd low = latent_squared_distances(latent);
  double penalty = 0;
  for (int i = 0; i < n; ++i) {
    const std::vector<int> by_high = neighbours_by(high, i), by_low = neighbours_by(low, i);
    std::vector<int> rank(static_cast<std::size_t>(n), 0);  // 1-based rank in the true order
    for (std::size_t r = 0; r < by_high.size(); ++r) rank[static_cast<std::size_t>(by_high[r])] = static_cast<int>(r) + 1;
    for (int r = 0; r < k; ++r) {
      const int true_rank = rank[static_cast<std::size_t>(by_low[static_cast<std::size_t>(r)])];
      if (true_rank > k) penalty += true_rank - k;
    }
  }
  const double nd = n, kd = k;
  const double value = 1.0 - 2.0 / (nd * kd * (2.0 * nd - 3.0 * kd - 1.0)) * penalty;
  // The normalisation is the largest possible penalty for k < n / 2 (Venna and Kaski).
  MATLAS_CHECK(value >= -1e-9 && value <= 1.0, "trustworthiness in [0, 1]");
  return value;
}

LayoutReadability layout_readability(const Eigen::MatrixXd& latent, double fraction) {
  LayoutReadability r;
  const Eigen::Index n = latent.rows();
  if (n < 2) return r;
  r.extent = (latent.colwise().maxCoeff() - latent.colwise().minCoeff()).norm();
  const Eigen::MatrixXd D = latent_squared_distances(latent);
  for (Eigen::Index i = 0; i < n; ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != i) nearest = std::min(nearest, D(i, j));
    if (std::sqrt(nearest) < fraction * r.extent) ++r.crowded;
  }
  r.crowded_share = static_cast<double>(r.crowded) / static_cast<double>(n);
  return r;
}

ManifoldQuality assess_manifold(const Model& model, const ManifoldQualityOptions& options, ProgressSink& progress) {
  ManifoldQuality out;
  const Eigen::MatrixXd& X = model.latent();
  const int n = model.count(), q = model.dim();
  out.layout = layout_readability(X);
  // Trustworthiness needs 2k < n - 1: small databases (the 8 Nielsen materials) use a smaller k.
  out.layout.neighbours = std::min(out.layout.neighbours, (n - 2) / 2);
  if (out.layout.neighbours >= 1) {
    progress.message("manifold quality: perceptual distances between the inputs");
    out.layout.trustworthiness =
        trustworthiness(perceptual_squared_distances(model, std::max(1, options.value_stride)), X, out.layout.neighbours);
  }
  out.inputs_max_albedo = model.material_albedo().maxCoeff();
  const std::vector<std::size_t> input_negatives = count_negative_inputs(model);
  out.input_negative_values =
      static_cast<int>(std::accumulate(input_negatives.begin(), input_negatives.end(), std::size_t{0}));

  // Midpoints of nearest-neighbour pairs (of an even spread of the materials), and random points
  // of the hull.
  const Eigen::MatrixXd D = latent_squared_distances(X);
  std::vector<Eigen::VectorXd> midpoints, hull;
  for (const int i : spread_indices(n, options.midpoints)) {
    const int j = neighbours_by(D, i).front();
    midpoints.push_back(0.5 * (X.row(i) + X.row(j)).transpose());
  }
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::exponential_distribution<double> expo(1.0);
  for (int p = 0; p < options.hull_points; ++p) {
    const int a = pick(rng), b = pick(rng), c = pick(rng);
    double wa = expo(rng), wb = expo(rng), wc = expo(rng);  // Dirichlet(1, 1, 1)
    const double s = wa + wb + wc;
    hull.push_back(((wa / s) * X.row(a) + (wb / s) * X.row(b) + (wc / s) * X.row(c)).transpose());
  }
  auto as_matrix = [&](const std::vector<Eigen::VectorXd>& points) {
    Eigen::MatrixXd P(static_cast<Eigen::Index>(points.size()), q);
    for (std::size_t k = 0; k < points.size(); ++k) P.row(static_cast<Eigen::Index>(k)) = points[k].transpose();
    return P;
  };
  for (const Interpolation mode : {Interpolation::convex, Interpolation::gp}) {
    for (const auto& [where, points] : {std::pair<const char*, const std::vector<Eigen::VectorXd>*>{"midpoints", &midpoints},
                                        {"hull", &hull}}) {
      progress.message(std::string("manifold quality: ") + to_string(mode) + " weights at " + where);
      const Eigen::MatrixXd W = model.predict_batch(as_matrix(*points), mode).weights;
      out.plausibility.push_back(
          summarise(model, W, out.inputs_max_albedo, input_negatives, options.negative_budget, to_string(mode), where));
    }
  }
  return out;
}

}  // namespace matlas::eval
