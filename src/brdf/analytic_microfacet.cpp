#include "brdf/analytic_microfacet.h"

#include <algorithm>
#include <cmath>

namespace matlas::microfacet {

double ggx_d(double cos_h, double alpha) {
  if (cos_h <= 0.0) return 0.0;
  const double a2 = alpha * alpha;
  const double c2 = cos_h * cos_h;
  // 1 + (a^2 - 1) cos^2 written as a^2 c^2 + (1 - c^2) to avoid cancellation near the peak.
  const double denom = a2 * c2 + std::max(0.0, 1.0 - c2);
  return a2 / (kPi * denom * denom);
}

double ggx_lambda(double cos_t, double alpha) {
  if (cos_t >= 1.0) return 0.0;
  if (cos_t <= 0.0) return HUGE_VAL;
  const double c2 = cos_t * cos_t;
  const double tan2 = std::max(0.0, 1.0 - c2) / c2;
  return 0.5 * (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

double smith_g1(double cos_t, double alpha) {
  if (cos_t <= 0.0) return 0.0;
  return 1.0 / (1.0 + ggx_lambda(cos_t, alpha));
}

double smith_g2_height_correlated(double cos_i, double cos_o, double alpha) {
  if (cos_i <= 0.0 || cos_o <= 0.0) return 0.0;
  return 1.0 / (1.0 + ggx_lambda(cos_i, alpha) + ggx_lambda(cos_o, alpha));
}

Rgb fresnel_schlick(const Rgb& f0, double cos_d) {
  const double m = 1.0 - std::clamp(cos_d, 0.0, 1.0);
  const double m2 = m * m;
  return f0 + (Rgb::Ones() - f0) * (m2 * m2 * m);
}

double fresnel_dielectric(double cos_d, double ior) {
  const double ci = std::clamp(cos_d, 0.0, 1.0);
  const double sin2_t = (1.0 - ci * ci) / (ior * ior);
  if (sin2_t >= 1.0) return 1.0;
  const double ct = std::sqrt(1.0 - sin2_t);
  const double rs = (ci - ior * ct) / (ci + ior * ct);
  const double rp = (ior * ci - ct) / (ior * ci + ct);
  return 0.5 * (rs * rs + rp * rp);
}

}  // namespace matlas::microfacet
