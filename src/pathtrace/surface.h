#pragma once
// The scattering of the scene's analytic surfaces (lambert, ggx) and the FIXED sampling density
// of the measured object. All directions are in the local frame (normal +z), wo towards the
// viewer, wi towards the light.
#include <vector>

#include "pathtrace/scene_spec.h"
#include "render/sampling_mixture.h"

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

/// The measured object's sampling density: render/sampling_mixture.h without its environment
/// strategy (a one-sample mixture of the cosine lobe and GGX lobes around the mirror direction, the
/// same for every material, so that the image is affine in the table). Environment and area
/// lights are sampled by next-event estimation and combined with it by multiple importance
/// sampling.
using FixedDensity = render::SamplingMixture;

/// The path tracer's default density: cosine 0.3, GGX lobes of alpha 0.02 (0.3) and 0.12 (0.4).
inline FixedDensity default_fixed_density() { return {0.0, 0.3, {{0.02, 0.3}, {0.12, 0.4}}}; }

}  // namespace matlas::pathtrace
