#pragma once
// Directional albedo a(wo) = integral over the hemisphere of f(wi, wo) cos(theta_i) dwi.
//
// Tables (MERL grid) are integrated in half-vector space, bin by bin: with wi = reflect(wo, h),
// dwi = 4 (wo.h) dwh, so
//   a(wo) = integral over h of f(h, wo) 4 (wo.h) cos(theta_i) sin(theta_h) dtheta_h dphi_h.
// theta_h is parameterised by MERL's square-root coordinate u (theta_h = u^2 pi/2, so
// dtheta_h = pi u du) and each theta_h bin [i/N, (i+1)/N) in u gets its own Gauss-Legendre
// points, times a midpoint rule in phi_h. Every theta_h bin, down to the narrowest one at the
// specular peak (0.011 degrees wide), is integrated with its exact extent: a near-mirror table
// whose energy sits in the first bins gets its albedo, which a regular grid of directions misses
// (chrome: 0.016 on a 256x256 cosine grid, about 0.095 here). The rule is a fixed list of (bin,
// weight) pairs per view angle: the albedo is a linear functional of the table.
//
// Analytic functors keep a cosine-weighted quadrature (midpoint rule in the unit square, mapped by
// Malley's method: a = pi * mean f over the points); for their sharp lobes see
// brdf/analytic_albedo.h.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "brdf/brdf_table.h"

namespace matlas {

/// Quadrature directions for albedo integrals of functors: `resolution`^2 cosine-distributed
/// directions.
std::vector<Vec3> cosine_quadrature(int resolution);

/// Outgoing direction at polar angle theta (radians) in the x-z plane.
inline Vec3 direction_at_theta(double theta) { return {std::sin(theta), 0.0, std::cos(theta)}; }

/// Directional albedo of any BRDF functor f(wi, wo) -> Rgb for the view direction wo, by the
/// cosine-weighted quadrature (smooth functions only).
template <class Brdf>
Rgb directional_albedo(const Brdf& f, const Vec3& wo, int resolution = 256) {
  Rgb sum = Rgb::Zero();
  const std::vector<Vec3> dirs = cosine_quadrature(resolution);
  for (const Vec3& wi : dirs) sum += f(wi, wo);
  return sum * (kPi / static_cast<double>(dirs.size()));
}

/// Resolution of the half-vector quadrature of tables.
struct AlbedoQuadrature {
  int theta_h_points = 2;  ///< Gauss-Legendre points per theta_h bin (1 to 4), in u
  int phi_h_points = 64;   ///< midpoint-rule azimuths of the half vector over [0, 2 pi)
};

/// One term of an albedo rule: weight * f(bin).
struct AlbedoTerm {
  std::size_t bin = 0;  ///< flat bin index (MerlDims::flat)
  double weight = 0;
};

/// The rule for the view direction at polar angle theta_o: a(theta_o) = sum of weight * f(bin),
/// sorted by bin, one term per bin. The bin of each point is MERL's nearest bin of (wi, wo), its
/// theta_h index the bin whose extent the Gauss points integrate. Directions with wi below the
/// horizon get no weight.
std::vector<AlbedoTerm> albedo_rule(const MerlDims& dims, double theta_o, const AlbedoQuadrature& q = {});

/// Directional albedo of a table by albedo_rule (missing values count as 0).
Rgb directional_albedo(const BrdfTable& table, double theta_o, const AlbedoQuadrature& q = {});

/// Directional albedo of f(wi, wo) by a quadrature over the half vector h instead of wi (wi is
/// wo reflected about h, dwi = 4 (wo.h) dh), with theta_h = (pi/2) u^2 and midpoints in u and
/// phi_h, the MERL grid's own refinement towards the mirror direction: resolves specular peaks
/// far narrower than a cosine quadrature's spacing. resolution x 2 resolution evaluations. For
/// a table, make resolution a multiple of its theta_h bins (the default 540 = 6 x 90): each bin then
/// gets the same number of points in u (512 gives 5 or 6, a weight error of up to 17 % per bin,
/// which shows as 0.8 % in the albedo of a material whose peak lies in a few bins).
/// visit_half_vector_quadrature calls visit(wi, weight) for each point of the rule (weight =
/// cos(theta_i) times the solid angle's share: the albedo is sum f(wi, wo) weight), for sums that
/// keep the terms apart (an albedo linear in a table's samples).
template <class Visit>
void visit_half_vector_quadrature(const Vec3& wo, int resolution, Visit&& visit) {
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
      visit(wi, wi.z() * 4.0 * c * jacobian);
    }
  }
}

/// half_vector_albedo's rule: sum of f(wi, wo) * weight over visit_half_vector_quadrature's points.
template <class Brdf>
Rgb half_vector_albedo(const Brdf& f, const Vec3& wo, int resolution = 540) {
  Rgb sum = Rgb::Zero();
  visit_half_vector_quadrature(wo, resolution, [&](const Vec3& wi, double weight) { sum += f(wi, wo) * weight; });
  return sum;
}

/// The normal albedo as a rendered view sees it: the directional albedo averaged over view
/// directions within `cone_deg` of the normal (solid-angle weights, `rings` rings at the midpoints
/// of equal steps in theta). At exactly 0 deg every (wi, wo) lies on the grid's diagonal theta_d =
/// theta_h, a slice of measure zero of each bin that a sub-degree specular peak notices (-23 % to
/// +22 % for RGL materials, chrome 0.016 for 0.095); a camera never looks along exactly one
/// direction, and from 0.5 deg on the bins are sampled across their extent.
Rgb normal_albedo(const BrdfTable& table, double cone_deg = 2.0, int rings = 4, const AlbedoQuadrature& q = {});

/// Albedo curve: a(theta_o) at `count` angles evenly spaced in [0, 90) degrees (bin centres).
std::vector<Rgb> albedo_curve(const BrdfTable& table, int count = 90, const AlbedoQuadrature& q = {});

/// A short description of the table rule, for model metadata.
std::string albedo_rule_description(const AlbedoQuadrature& q = {});

}  // namespace matlas
