#include "manifold/plausibility.h"

#include <algorithm>

#include "manifold/dense_product.h"
#include "manifold/model.h"

namespace matlas {

double Plausibility::violation() const {
  return negative_fraction + std::max(0.0, max_albedo - 1.0) + std::max(0.0, -min_albedo);
}

PlausibilityProbe::PlausibilityProbe(const Model& model, std::size_t samples)
    : model_(model), n_(model.count()) {
  const std::size_t kept = model.kept_columns();
  const std::size_t count = std::min(samples, kept);
  values_.resize(count * static_cast<std::size_t>(n_));
  means_.resize(count);
  for (std::size_t s = 0; s < count; ++s) {
    const std::size_t c = (2 * s + 1) * kept / (2 * count);  // centres of count equal strata
    model.data(c, values_.data() + s * static_cast<std::size_t>(n_));
    means_[s] = model.mean(c);
  }
  centred_.resize(static_cast<Eigen::Index>(count), n_);
  for (std::size_t s = 0; s < count; ++s)
    for (int i = 0; i < n_; ++i)
      centred_(static_cast<Eigen::Index>(s), i) =
          static_cast<double>(values_[s * static_cast<std::size_t>(n_) + static_cast<std::size_t>(i)]) - means_[s];
}

std::vector<Plausibility> PlausibilityProbe::batch(const Eigen::MatrixXd& W) const {
  // value = (1 - sum w) mean + sum w z = mean + sum w (z - mean)
  const Eigen::MatrixXd values = blas_product(centred_, W);
  const Eigen::MatrixXd albedo = model_.albedo_batch(W);
  std::vector<Plausibility> out(static_cast<std::size_t>(W.cols()));
  for (Eigen::Index j = 0; j < W.cols(); ++j) {
    std::size_t negative = 0;
    for (Eigen::Index s = 0; s < values.rows(); ++s) negative += values(s, j) + means_[static_cast<std::size_t>(s)] < 0.0;
    Plausibility& p = out[static_cast<std::size_t>(j)];
    p.negative_fraction = values.rows() ? static_cast<double>(negative) / static_cast<double>(values.rows()) : 0.0;
    p.max_albedo = albedo.col(j).maxCoeff();
    p.min_albedo = albedo.col(j).minCoeff();
  }
  return out;
}

Plausibility PlausibilityProbe::operator()(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  Plausibility p;
  const double mean_weight = 1.0 - w.sum();
  std::size_t negative = 0;
  for (std::size_t s = 0; s < means_.size(); ++s) {
    const float* z = values_.data() + s * static_cast<std::size_t>(n_);
    double v = mean_weight * means_[s];
    for (int i = 0; i < n_; ++i) v += w[i] * z[i];
    negative += v < 0.0;
  }
  p.negative_fraction = means_.empty() ? 0.0 : static_cast<double>(negative) / static_cast<double>(means_.size());
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
