#pragma once
// Directional albedo of sharp lobes by deterministic importance sampling of the half vector.
//
// The cosine quadrature of brdf/albedo.h cannot resolve a near-specular lobe (a GGX lobe with
// alpha = 0.02 covers a few quadrature points at best). Here wi is generated from a midpoint grid
// in the unit square mapped through a distribution of half vectors h with density p(h) (solid
// angle), wi = reflect(wo, h), and
//   a(wo) = mean over the grid of f(wi, wo) cos_i / p(wi),   p(wi) = p(h) / (4 |wo.h|),
// which is exact in the limit and converges fast when p matches the lobe.
#include <cmath>

#include "brdf/analytic_microfacet.h"
#include "brdf/types.h"

namespace matlas {

/// Half vectors distributed like the GGX normals: p(h) = D(h) cos(theta_h).
struct GgxHalfSampler {
  double alpha = 0.1;
  /// Maps (u1, u2) in [0, 1)^2 to a half vector: tan^2(theta_h) = alpha^2 u1 / (1 - u1).
  Vec3 sample(double u1, double u2) const {
    const double tan2 = alpha * alpha * u1 / (1.0 - u1);
    const double cos_t = 1.0 / std::sqrt(1.0 + tan2);
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    const double phi = 2.0 * kPi * u2;
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
  }
  double pdf(const Vec3& h) const { return microfacet::ggx_d(h.z(), alpha) * h.z(); }
};

/// Half vectors distributed like a Blinn-Phong lobe: p(h) = (n + 2) / (2 pi) cos^(n+1)(theta_h).
struct PhongHalfSampler {
  double exponent = 100.0;
  Vec3 sample(double u1, double u2) const {
    const double cos_t = std::pow(1.0 - u1, 1.0 / (exponent + 2.0));
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    const double phi = 2.0 * kPi * u2;
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
  }
  double pdf(const Vec3& h) const {
    return h.z() <= 0.0 ? 0.0 : (exponent + 2.0) / (2.0 * kPi) * std::pow(h.z(), exponent + 1.0);
  }
};

/// Directional albedo of f(wi, wo) -> Rgb for view direction wo by importance sampling half
/// vectors with `sampler` on a resolution x resolution midpoint grid. Only the part of f that the
/// sampler reaches is integrated: use it for specular lobes, and the cosine quadrature for
/// smooth (diffuse) terms.
template <class Brdf, class HalfSampler>
Rgb half_vector_albedo(const Brdf& f, const Vec3& wo, const HalfSampler& sampler, int resolution = 256) {
  Rgb sum = Rgb::Zero();
  for (int a = 0; a < resolution; ++a) {
    const double u1 = (a + 0.5) / resolution;
    for (int b = 0; b < resolution; ++b) {
      const Vec3 h = sampler.sample(u1, (b + 0.5) / resolution);
      const double o_h = wo.dot(h);
      if (o_h <= 0.0) continue;
      const Vec3 wi = 2.0 * o_h * h - wo;
      if (wi.z() <= 0.0) continue;
      const double pdf_h = sampler.pdf(h);
      if (!(pdf_h > 0.0)) continue;
      sum += f(wi, wo) * (wi.z() * 4.0 * o_h / pdf_h);
    }
  }
  return sum / (static_cast<double>(resolution) * resolution);
}

}  // namespace matlas
