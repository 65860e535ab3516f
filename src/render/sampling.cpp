#include "render/sampling.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace matlas::render {

Distribution1D::Distribution1D(std::span<const double> weights) : weights_(weights.begin(), weights.end()) {
  const std::size_t n = weights_.size();
  double total = 0;
  for (double w : weights_) total += std::max(w, 0.0);
  if (!(total > 0) || !std::isfinite(total)) {
    std::fill(weights_.begin(), weights_.end(), 1.0);
    total = static_cast<double>(n);
  }
  for (double& w : weights_) w = std::max(w, 0.0);
  cdf_.resize(n + 1);
  cdf_[0] = 0;
  for (std::size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + weights_[i] / total;
  cdf_[n] = 1.0;
  integral_ = total / static_cast<double>(n);
}

double Distribution1D::sample(double u, int* cell, double* pdf_out) const {
  MATLAS_DCHECK(!weights_.empty() && cdf_.size() == weights_.size() + 1, "a constructed distribution");
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cdf_.begin() - 1, 0));
  i = std::min(i, weights_.size() - 1);
  while (weights_[i] <= 0 && i + 1 < weights_.size()) ++i;  // never return an empty cell
  const double span = cdf_[i + 1] - cdf_[i];
  double t = span > 0 ? (u - cdf_[i]) / span : 0.5;
  t = std::clamp(t, 0.0, std::nextafter(1.0, 0.0));
  if (cell) *cell = static_cast<int>(i);
  if (pdf_out) {
    *pdf_out = pdf(static_cast<int>(i));
    MATLAS_DCHECK(*pdf_out >= 0);
  }
  return std::min((static_cast<double>(i) + t) * cell_width(), std::nextafter(1.0, 0.0));
}

Distribution2D::Distribution2D(std::span<const double> weights, int cols, int rows)
    : cols_(cols), rows_(rows) {
  MATLAS_CHECK(cols > 0 && rows > 0, "a non-empty 2D distribution");
  MATLAS_CHECK_EQ(weights.size(), static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows));
  std::vector<double> row_weight(static_cast<std::size_t>(rows));
  conditional_.reserve(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    conditional_.emplace_back(weights.subspan(static_cast<std::size_t>(r) * static_cast<std::size_t>(cols),
                                              static_cast<std::size_t>(cols)));
    double sum = 0;
    for (int c = 0; c < cols; ++c) sum += std::max(weights[static_cast<std::size_t>(r * cols + c)], 0.0);
    row_weight[static_cast<std::size_t>(r)] = sum;
  }
  marginal_ = Distribution1D(row_weight);
}

void Distribution2D::sample(double u0, double u1, double* u, double* v, double* pdf_out) const {
  int row = 0, col = 0;
  double pdf_row = 0, pdf_col = 0;
  *v = marginal_.sample(u1, &row, &pdf_row);
  MATLAS_DCHECK(row >= 0 && row < rows_, "the marginal picks a row");
  *u = conditional_[static_cast<std::size_t>(row)].sample(u0, &col, &pdf_col);
  *pdf_out = pdf_row * pdf_col;
}

double Distribution2D::pdf(double u, double v) const {
  const int col = std::clamp(static_cast<int>(u * cols_), 0, cols_ - 1);
  const int row = std::clamp(static_cast<int>(v * rows_), 0, rows_ - 1);
  return marginal_.pdf(row) * conditional_[static_cast<std::size_t>(row)].pdf(col);
}

void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double c = n.x() * n.y() * a;
  t = Vec3(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Vec3(c, sign + n.y() * n.y() * a, -n.y());
}

Vec3 sample_cosine(double u0, double u1) {
  const double r = std::sqrt(u0), phi = 2.0 * kPi * u1;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u0))};
}

Vec3 sample_ggx_reflection(const Vec3& wo, double alpha, double u0, double u1) {
  // D(h) cos(theta_h) sampling: tan^2(theta_h) = alpha^2 u / (1 - u).
  const double tan2 = alpha * alpha * u0 / std::max(1.0 - u0, 1e-300);
  const double cos_h = 1.0 / std::sqrt(1.0 + tan2);
  const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
  const double phi = 2.0 * kPi * u1;
  const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
  return 2.0 * wo.dot(h) * h - wo;
}

double ggx_reflection_pdf(const Vec3& wo, const Vec3& wi, double alpha) {
  if (wi.z() <= 0 || wo.z() <= 0) return 0.0;
  const Vec3 h = (wi + wo).normalized();
  const double cos_h = h.z(), a2 = alpha * alpha;
  const double d = cos_h * cos_h * (a2 - 1.0) + 1.0;
  const double D = a2 / (kPi * d * d);
  const double o_h = wo.dot(h);
  return o_h > 0 ? D * cos_h / (4.0 * o_h) : 0.0;
}

}  // namespace matlas::render
