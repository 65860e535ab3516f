#pragma once
// Building blocks of the analytic microfacet BRDFs: the GGX (Trowbridge-Reitz) distribution of
// normals, Smith masking-shadowing for it, and Fresnel reflectance (Schlick, exact dielectric).
//
// Conventions: local frame with the normal along +z; `alpha` is the GGX width parameter itself
// (isotropic; alpha = r^2 for a "perceptual" roughness r, but matlas exposes alpha everywhere).
// Cosines are of angles measured from the macro normal unless said otherwise.
#include "brdf/types.h"

namespace matlas::microfacet {

/// Smallest alpha accepted by the analytic BRDFs (a narrower lobe is below the MERL grid's
/// resolution and makes D overflow-prone).
inline constexpr double kMinAlpha = 1e-3;

/// GGX distribution of normals D(h) for a microfacet normal with cos(theta_h) = cos_h, normalised
/// so that the integral of D(h) cos(theta_h) over the hemisphere is 1. Zero for cos_h <= 0.
double ggx_d(double cos_h, double alpha);

/// Smith Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2 for a direction with
/// cos(theta) = cos_t > 0.
double ggx_lambda(double cos_t, double alpha);

/// Smith masking of one direction: G1 = 1 / (1 + Lambda).
double smith_g1(double cos_t, double alpha);

/// Smith height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wi) + Lambda(wo)) (Heitz 2014,
/// "Understanding the masking-shadowing function"), symmetric in its two directions.
double smith_g2_height_correlated(double cos_i, double cos_o, double alpha);

/// Schlick's Fresnel approximation with a coloured reflectance at normal incidence:
/// F = F0 + (1 - F0) (1 - cos)^5. `cos_d` is the cosine between the light and the microfacet
/// normal (clamped into [0, 1]).
Rgb fresnel_schlick(const Rgb& f0, double cos_d);

/// Exact unpolarised Fresnel reflectance of a dielectric interface (outside IOR 1, inside `ior`)
/// for light arriving from outside at cos(theta) = cos_d; 1 beyond total internal reflection
/// (only possible when ior < 1).
double fresnel_dielectric(double cos_d, double ior);

/// Reflectance at normal incidence of a dielectric: ((ior - 1) / (ior + 1))^2.
inline double dielectric_f0(double ior) {
  const double r = (ior - 1.0) / (ior + 1.0);
  return r * r;
}

}  // namespace matlas::microfacet
