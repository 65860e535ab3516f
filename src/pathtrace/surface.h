#pragma once
// The scattering of the scene's analytic surfaces (lambert, ggx) and the FIXED sampling density
// of the measured object. All directions are in the local frame (normal +z), wo towards the
// viewer, wi towards the light.
#include <vector>

#include "pathtrace/scene_spec.h"

namespace matlas::pathtrace {

/// GGX normal distribution D(h) for cos(theta_h) = cos_h.
double ggx_d(double cos_h, double alpha);
/// Height-correlated Smith masking-shadowing G2(wi, wo).
double ggx_g2(const Vec3& wi, const Vec3& wo, double alpha);

/// f(wi, wo) of a lambert or ggx surface (0 below the horizon).
Rgb surface_eval(const SurfaceSpec& s, const Vec3& wi, const Vec3& wo);
/// Draws wi for a lambert or ggx surface (a mixture of the cosine lobe and the GGX lobe, by the
/// lobes' reflectances at normal incidence); returns the density per unit solid angle (0 when the
/// draw fell below the horizon).
double surface_sample(const SurfaceSpec& s, const Vec3& wo, double u0, double u1, double u2, Vec3* wi);
double surface_pdf(const SurfaceSpec& s, const Vec3& wo, const Vec3& wi);

/// The measured object's sampling density: a one-sample mixture of the cosine lobe and GGX lobes
/// of fixed widths around the mirror direction, the same for every material (so that the image
/// is affine in the table). Environment and area lights are sampled by next-event estimation and
/// combined with this density by multiple importance sampling.
struct FixedDensity {
  double cosine = 0.3;
  /// (alpha, probability) of the GGX lobes; with `cosine`, normalised to sum 1.
  std::vector<std::pair<double, double>> lobes = {{0.02, 0.3}, {0.12, 0.4}};

  double sample(const Vec3& wo, double u0, double u1, double u2, Vec3* wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  /// Throws matlas::Error for negative or all-zero probabilities or alphas out of (0, 1].
  void validate() const;
};

}  // namespace matlas::pathtrace
