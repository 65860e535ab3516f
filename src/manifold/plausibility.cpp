#include "manifold/plausibility.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "manifold/dense_product.h"
#include "manifold/model.h"

namespace matlas {

double Plausibility::violation() const {
  return negative_fraction + std::max(0.0, max_albedo - 1.0) + std::max(0.0, -min_albedo);
}

PlausibilityProbe::PlausibilityProbe(const Model& model, std::size_t samples) : model_(model) {
  const std::size_t kept = model.kept_columns();
  const auto count = static_cast<Eigen::Index>(std::min(samples, kept));
  const int n = model.count();
  std::vector<float> z(static_cast<std::size_t>(n));
  means_.resize(count);
  centred_.resize(count, n);
  for (Eigen::Index s = 0; s < count; ++s) {
    // The centre of each of `count` equal strata of the kept columns.
    const std::size_t c = (2 * static_cast<std::size_t>(s) + 1) * kept / (2 * static_cast<std::size_t>(count));
    MATLAS_CHECK_LT(c, kept);
    model.data(c, z.data());
    means_[s] = model.mean(c);
    for (int i = 0; i < n; ++i) centred_(s, i) = static_cast<double>(z[static_cast<std::size_t>(i)]) - means_[s];
  }
  // Input i: its sampled values are the stored ones, its albedo curve a row of material_albedo.
  const Eigen::MatrixXd& albedo = model.material_albedo();
  MATLAS_CHECK_EQ(albedo.rows(), n);
  input_plausible_.assign(static_cast<std::size_t>(n), 1);
  for (int i = 0; i < n; ++i) {
    bool ok = albedo.cols() == 0 || (albedo.row(i).minCoeff() >= 0.0 && albedo.row(i).maxCoeff() <= 1.0);
    for (Eigen::Index s = 0; s < count && ok; ++s) ok = centred_(s, i) + means_[s] >= 0.0;
    input_plausible_[static_cast<std::size_t>(i)] = ok;
  }
  inputs_plausible_ = std::all_of(input_plausible_.begin(), input_plausible_.end(), [](char ok) { return ok != 0; });
}

bool PlausibilityProbe::input_plausible(int i) const {
  MATLAS_CHECK(i >= 0 && static_cast<std::size_t>(i) < input_plausible_.size(), "an input of the model");
  return input_plausible_[static_cast<std::size_t>(i)] != 0;
}

bool PlausibilityProbe::plausible_by_construction(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  MATLAS_CHECK_EQ(static_cast<std::size_t>(w.size()), input_plausible_.size());
  double sum = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    if (w[i] < 0.0 || (w[i] > 0.0 && !input_plausible_[static_cast<std::size_t>(i)])) return false;
    sum += w[i];
  }
  return std::abs(sum - 1.0) <= 1e-9;
}

namespace {

/// Share of negative entries of mean + column j of `centred_values`.
double negative_share(const Eigen::Ref<const Eigen::VectorXd>& centred_values, const Eigen::VectorXd& means) {
  MATLAS_CHECK_EQ(centred_values.size(), means.size());
  if (means.size() == 0) return 0.0;
  // Values below -1e-12 of their column's mean: a combination summing to 1 reads an exact zero of
  // the inputs as mean + sum_i w_i (0 - mean), which rounds to +-1e-16 of the mean.
  return static_cast<double>(((centred_values + means).array() < -1e-12 * means.array().abs()).count()) /
         static_cast<double>(means.size());
}

}  // namespace

std::vector<Plausibility> PlausibilityProbe::batch(const Eigen::MatrixXd& W) const {
  // A value is mean + sum_i w_i (z_i - mean) = (1 - sum w) mean + sum_i w_i z_i.
  MATLAS_CHECK_EQ(W.rows(), centred_.cols());
  const Eigen::MatrixXd values = blas_product(centred_, W);
  const Eigen::MatrixXd albedo = model_.albedo_batch(W);
  std::vector<Plausibility> out(static_cast<std::size_t>(W.cols()));
  for (Eigen::Index j = 0; j < W.cols(); ++j) {
    Plausibility& p = out[static_cast<std::size_t>(j)];
    p.negative_fraction = negative_share(values.col(j), means_);
    p.max_albedo = albedo.col(j).maxCoeff();
    p.min_albedo = albedo.col(j).minCoeff();
  }
  return out;
}

Plausibility PlausibilityProbe::operator()(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  MATLAS_CHECK_EQ(w.size(), centred_.cols());
  Plausibility p;
  p.negative_fraction = negative_share(centred_ * w, means_);
  const std::vector<Rgb> albedo = model_.albedo_curve(w);
  p.max_albedo = -1e300;
  p.min_albedo = 1e300;
  for (const Rgb& a : albedo) {
    p.max_albedo = std::max(p.max_albedo, a.maxCoeff());
    p.min_albedo = std::min(p.min_albedo, a.minCoeff());
  }
  return p;
}

}  // namespace matlas
