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

/// Directional albedo of a table (nearest-bin lookup, missing values as 0).
Rgb directional_albedo(const BrdfTable& table, double theta_o, int resolution = 256);

/// Albedo curve: a(theta_o) at `count` angles evenly spaced in [0, 90) degrees (bin centres).
std::vector<Rgb> albedo_curve(const BrdfTable& table, int count = 90, int resolution = 128);

}  // namespace matlas
