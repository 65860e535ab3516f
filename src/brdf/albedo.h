#pragma once
// Directional albedo a(wo) = integral over the hemisphere of f(wi, wo) cos(theta_i) dwi, by a
// deterministic cosine-weighted quadrature (midpoint rule in the unit square, mapped by Malley's
// method), so that a = pi * mean f over the quadrature points.
#include <cmath>
#include <vector>

#include "brdf/brdf_table.h"

namespace matlas {

/// Quadrature directions for albedo integrals: `resolution`^2 cosine-distributed directions.
std::vector<Vec3> cosine_quadrature(int resolution);

/// Outgoing direction at polar angle theta (radians) in the x-z plane.
inline Vec3 direction_at_theta(double theta) { return {std::sin(theta), 0.0, std::cos(theta)}; }

/// Directional albedo of any BRDF functor f(wi, wo) -> Rgb for the view direction wo.
template <class Brdf>
Rgb directional_albedo(const Brdf& f, const Vec3& wo, int resolution = 256) {
  Rgb sum = Rgb::Zero();
  const std::vector<Vec3> dirs = cosine_quadrature(resolution);
  for (const Vec3& wi : dirs) sum += f(wi, wo);
  return sum * (kPi / static_cast<double>(dirs.size()));
}

/// Directional albedo of f(wi, wo) by a quadrature over the half vector h instead of wi (wi is
/// wo reflected about h, dwi = 4 (wo.h) dh), with theta_h = (pi/2) u^2 and midpoints in u and
/// phi_h, the MERL grid's own refinement towards the mirror direction: resolves specular peaks
/// far narrower than a cosine quadrature's spacing. resolution x 2 resolution evaluations.
template <class Brdf>
Rgb half_vector_albedo(const Brdf& f, const Vec3& wo, int resolution = 512) {
  Rgb sum = Rgb::Zero();
  const int n_u = resolution, n_phi = 2 * resolution;
  const double du = 1.0 / n_u, dphi = 2.0 * kPi / n_phi;
  for (int a = 0; a < n_u; ++a) {
    const double u = (a + 0.5) * du, theta_h = 0.5 * kPi * u * u;
    const double jacobian = std::sin(theta_h) * kPi * u * du * dphi;  // dh = sin(theta_h) dtheta_h dphi_h
    for (int b = 0; b < n_phi; ++b) {
      const double phi_h = (b + 0.5) * dphi;
      const Vec3 h(std::sin(theta_h) * std::cos(phi_h), std::sin(theta_h) * std::sin(phi_h), std::cos(theta_h));
      const double c = wo.dot(h);
      if (c <= 0) continue;
      const Vec3 wi = 2.0 * c * h - wo;
      if (wi.z() <= 0) continue;
      sum += f(wi, wo) * (wi.z() * 4.0 * c * jacobian);
    }
  }
  return sum;
}

/// Directional albedo of a table (nearest-bin lookup, missing values as 0).
Rgb directional_albedo(const BrdfTable& table, double theta_o, int resolution = 256);

/// Albedo curve: a(theta_o) at `count` angles evenly spaced in [0, 90) degrees (bin centres).
std::vector<Rgb> albedo_curve(const BrdfTable& table, int count = 90, int resolution = 128);

}  // namespace matlas
