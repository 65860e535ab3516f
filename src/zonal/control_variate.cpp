#include "zonal/control_variate.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"
#include "render/sampling.h"
#include "zonal/lobes.h"
#include "zonal/sh.h"

namespace matlas::zonal {

namespace {

const PrefilteredEnvironment& checked(const std::shared_ptr<const PrefilteredEnvironment>& environment) {
  MATLAS_CHECK(environment != nullptr, "a control variate's environment");
  return *environment;
}

}  // namespace

ProjectionSettings control_projection_settings() {
  ProjectionSettings s;
  s.bands = 16;
  s.theta_o_count = 32;
  s.lobes = kDefaultLobes;
  return s;
}

PrefilterSettings control_prefilter_settings() {
  PrefilterSettings s;
  s.bands = 16;
  s.texels_per_band = 32;
  s.lobes = kDefaultLobes;
  s.lobe_rows = 1025;
  s.scale_lobe_rows = true;
  return s;
}

ZonalControlVariate::ZonalControlVariate(const ZonalCoefficients& coefficients,
                                         std::shared_ptr<const PrefilteredEnvironment> environment_pointer, int lobes)
    : coefficients_(coefficients), basis_(coefficients.bands), keep_(std::move(environment_pointer)),
      environment_(checked(keep_)), legendre_(coefficients.bands) {
  const PrefilteredEnvironment& environment = environment_;
  if (coefficients.bands > environment.bands())
    throw Error("control variate: coefficients of " + std::to_string(coefficients.bands) +
                " bands, environment of " + std::to_string(environment.bands()));
  if (coefficients.lobes != environment.lobes())
    throw Error("control variate: the coefficients' lobes differ from the environment's lobe maps");
  lobes_ = lobes < 0 ? coefficients.lobes.size() : std::min(coefficients.lobes.size(), static_cast<std::size_t>(lobes));
  const std::size_t K = coefficients.zonal_size(), S = coefficients.size();
  const int L = coefficients.bands, T = coefficients.theta_o_count;
  MATLAS_CHECK_EQ(coefficients.values.size(), static_cast<std::size_t>(T) * S * 3);
  // A_l[m][k] = sqrt(4 pi / (2l + 1)) Y_l^m(d_{l,k}), d_{l,k} at phi = 0.
  std::vector<std::vector<double>> A(static_cast<std::size_t>(L) + 1);
  std::vector<double> p;
  for (int l = 0; l <= L; ++l) {
    std::vector<double>& a = A[static_cast<std::size_t>(l)];
    a.assign(static_cast<std::size_t>((l + 1) * (l + 1)), 0.0);
    for (int k = 0; k <= l; ++k) {
      normalized_legendre(l, std::cos(basis_.alpha(lm_index(l, k))), p);
      for (int m = 0; m <= l; ++m)
        a[static_cast<std::size_t>(m * (l + 1) + k)] =
            std::sqrt(4.0 * kPi / (2 * l + 1)) * (m > 0 ? std::sqrt(2.0) : 1.0) * p[lm_index(l, m)];
    }
  }
  for (std::size_t j = 0; j < K; ++j) {
    sin_alpha_.push_back(std::sin(basis_.alpha(j)));
    cos_alpha_.push_back(std::cos(basis_.alpha(j)));
  }
  harmonics_.assign(static_cast<std::size_t>(T) * S * 3, 0.0);
  for (int t = 0; t < T; ++t) {
    const double* lambda = &coefficients.values[static_cast<std::size_t>(t) * S * 3];
    double* out = &harmonics_[static_cast<std::size_t>(t) * S * 3];
    for (int l = 0; l <= L; ++l) {
      const std::vector<double>& a = A[static_cast<std::size_t>(l)];
      for (int m = 0; m <= l; ++m)
        for (int k = 0; k <= l; ++k) {
          const double w = a[static_cast<std::size_t>(m * (l + 1) + k)];
          for (int c = 0; c < 3; ++c) out[lm_index(l, m) * 3 + c] += w * lambda[lm_index(l, k) * 3 + c];
        }
    }
    for (std::size_t j = K * 3; j < S * 3; ++j) out[j] = lambda[j];
  }
}

namespace {

/// The slice's frame at a surface point: x along wo's tangential part, theta_o's interpolation.
struct SliceFrame {
  SliceFrame(const ZonalCoefficients& c, const Vec3& n, const Vec3& wo) {
    cos_o = std::clamp(n.dot(wo), -1.0, 1.0);
    MATLAS_DCHECK(cos_o > 0, "the view above the surface");
    x = wo - cos_o * n;
    if (x.norm() < 1e-9) {  // normal incidence: the slice is symmetric about n
      Vec3 y;
      render::orthonormal_basis(n, x, y);
    }
    x.normalize();
    c.interpolation(std::acos(cos_o), &t0, &f);
    const std::size_t S = c.size();
    a = &c.values[static_cast<std::size_t>(t0) * S * 3];
    b = c.theta_o_count > 1 ? a + S * 3 : a;
  }
  Rgb lambda(std::size_t j) const {
    return {(1 - f) * a[3 * j] + f * b[3 * j], (1 - f) * a[3 * j + 1] + f * b[3 * j + 1], (1 - f) * a[3 * j + 2] + f * b[3 * j + 2]};
  }
  double cos_o;
  Vec3 x;
  int t0;
  double f;
  const double* a;
  const double* b;
};

}  // namespace

Rgb ZonalControlVariate::smooth_integral(const Vec3& n, const Vec3& wo) const {
  const SliceFrame s(coefficients_, n, wo);
  Rgb sum = Rgb::Zero();
  for (std::size_t j = 0; j < coefficients_.zonal_size(); ++j)
    sum += s.lambda(j) * environment_.lookup(basis_.band(j), sin_alpha_[j] * s.x + cos_alpha_[j] * n);
  return sum;
}

Rgb ZonalControlVariate::sharp_integral(const Vec3& n, const Vec3& wo) const {
  if (lobes_ == 0) return Rgb::Zero();
  const SliceFrame s(coefficients_, n, wo);
  const Vec3 r = 2.0 * s.cos_o * n - wo;
  Rgb sum = Rgb::Zero();
  for (std::size_t i = 0; i < lobes_; ++i) sum += s.lambda(coefficients_.zonal_size() + i) * environment_.lobe_lookup(i, r);
  return sum;
}

Rgb ZonalControlVariate::eval(const Vec3& wi, const Vec3& wo) const {
  // The renderer asks for both taps of a camera sample with the same wo: theta_o's
  // interpolation once (it depends on theta_o and the sample count only).
  thread_local int last_count = 0, t0 = 0;
  thread_local double last_cos = 2.0, f = 0.0;
  if (wo.z() != last_cos || last_count != coefficients_.theta_o_count) {
    last_count = coefficients_.theta_o_count;
    last_cos = wo.z();
    coefficients_.interpolation(std::acos(std::clamp(wo.z(), -1.0, 1.0)), &t0, &f);
  }
  const int L = coefficients_.bands;
  const std::size_t K = coefficients_.zonal_size(), S = coefficients_.size();
  const double* a = &harmonics_[static_cast<std::size_t>(t0) * S * 3];
  const double* b = coefficients_.theta_o_count > 1 ? a + S * 3 : a;
  // The azimuth of wi from wo's (the slice's frame has wo in the x-z plane, x >= 0).
  const double ro = std::hypot(wo.x(), wo.y()), ri = std::hypot(wi.x(), wi.y());
  const double cos_phi = ro > 1e-12 && ri > 1e-12 ? std::clamp((wi.x() * wo.x() + wi.y() * wo.y()) / (ro * ri), -1.0, 1.0)
                                                 : 1.0;
  thread_local std::vector<double> p, cos_m;
  p.resize(triangle_size(L));
  legendre_.evaluate(std::clamp(wi.z(), -1.0, 1.0), p.data());
  cos_m.resize(static_cast<std::size_t>(L) + 1);
  cos_m[0] = 1.0;
  if (L > 0) cos_m[1] = cos_phi;
  for (int m = 2; m <= L; ++m)
    cos_m[static_cast<std::size_t>(m)] = 2.0 * cos_phi * cos_m[static_cast<std::size_t>(m - 1)] - cos_m[static_cast<std::size_t>(m - 2)];
  double s[3] = {0, 0, 0};
  for (int m = 1; m <= L; ++m) cos_m[static_cast<std::size_t>(m)] *= std::sqrt(2.0);  // the real harmonics' factor
  double sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0};  // the two theta_o samples' sums, mixed once
  for (int l = 0; l <= L; ++l)
    for (int m = 0; m <= l; ++m) {
      const std::size_t j = lm_index(l, m);
      const double y = p[j] * cos_m[static_cast<std::size_t>(m)];
      for (int c = 0; c < 3; ++c) {
        sa[c] += y * a[3 * j + c];
        sb[c] += y * b[3 * j + c];
      }
    }
  for (int c = 0; c < 3; ++c) s[c] = (1 - f) * sa[c] + f * sb[c];
  const Vec3 r(-wo.x(), -wo.y(), wo.z());
  for (std::size_t i = 0; i < lobes_; ++i) {
    const std::size_t j = K + i;
    const double k = lobe_value(coefficients_.lobes[i], r.dot(wi));
    for (int c = 0; c < 3; ++c) s[c] += k * ((1 - f) * a[3 * j + c] + f * b[3 * j + c]);
  }
  return {s[0], s[1], s[2]};
}

}  // namespace matlas::zonal
