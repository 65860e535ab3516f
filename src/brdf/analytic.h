#pragma once
// Analytic isotropic BRDFs, used to make synthetic MERL-like databases and as ground truth in
// tests. Each is a small value type, callable as f(wi, wo) -> Rgb with unit directions in the local
// frame (normal +z); every model returns 0 when wi or wo is at or below the horizon. All are
// reciprocal, non-negative, and conserve energy (directional albedo <= 1) for the documented
// parameter ranges; `validate()` throws matlas::Error for parameters outside them.
// See docs/ANALYTIC.md for the formulas.
#include <string>
#include <variant>

#include "brdf/types.h"

namespace matlas {

/// Lambertian diffuse: f = albedo / pi. Energy-conserving for albedo in [0, 1].
struct Lambertian {
  Rgb albedo = Rgb::Constant(0.8);

  Rgb operator()(const Vec3& wi, const Vec3& wo) const;
  void validate() const;
};

/// GGX (Trowbridge-Reitz) microfacet conductor:
///   f = D(h) G2(wi, wo) F(wi.h) / (4 cos_i cos_o)
/// with the Smith height-correlated G2 and Schlick's Fresnel with a coloured F0 (reflectance at
/// normal incidence, in [0, 1]). `alpha` is the GGX width itself (not a perceptual roughness),
/// in [microfacet::kMinAlpha, 1]. Single scattering only: rough conductors lose some energy
/// (albedo < F0 for large alpha), as in most real-time and offline renderers.
struct GgxConductor {
  Rgb f0 = Rgb::Constant(0.9);
  double alpha = 0.1;

  Rgb operator()(const Vec3& wi, const Vec3& wo) const;
  void validate() const;
};

/// Rough dielectric coating over a Lambertian base ("plastic"):
///   f = D G2 F_d(wi.h) / (4 cos_i cos_o) * specular
///     + diffuse / pi * (1 - F_d(cos_i)) (1 - F_d(cos_o))
/// with GGX D, Smith height-correlated G2 and the exact dielectric Fresnel F_d for the coating's
/// IOR. The base is seen through the coating twice (in and out), hence the two transmittance
/// factors; the factorised form keeps the model reciprocal. `specular` scales the coating (1 for a
/// physical coating, lower values mimic a thin or dusty coat). Energy-conserving for diffuse and
/// specular in [0, 1] and ior in [1, 2] (tested; see docs/ANALYTIC.md).
struct RoughPlastic {
  Rgb diffuse = Rgb::Constant(0.5);
  double alpha = 0.1;
  double ior = 1.5;
  double specular = 1.0;

  Rgb operator()(const Vec3& wi, const Vec3& wo) const { return specular_part(wi, wo) + diffuse_part(wi, wo); }
  /// The coating's reflection alone (a sharp lobe for small alpha).
  Rgb specular_part(const Vec3& wi, const Vec3& wo) const;
  /// The base's contribution alone (smooth).
  Rgb diffuse_part(const Vec3& wi, const Vec3& wo) const;
  void validate() const;
};

/// Normalised Blinn-Phong plus an optional Lambertian term:
///   f = diffuse / pi + specular * c(n) cos^n(theta_h),
///   c(n) = (n + 2)(n + 4) / (8 pi (2^(-n/2) + n)).
/// c(n) is the exact normalisation for which the specular lobe's directional albedo at normal
/// incidence is exactly `specular` (and lower at every other angle). The often quoted
/// (n + 2) / (2 pi) is the normalisation of the Phong lobe around the mirror direction; applied to
/// cos(theta_h) it gives albedos up to about 4 * specular for large n. Energy-conserving when
/// diffuse + specular <= 1 per channel; exponent n >= 0.
struct BlinnPhong {
  Rgb specular = Rgb::Constant(0.04);
  double exponent = 100.0;
  Rgb diffuse = Rgb::Zero();

  Rgb operator()(const Vec3& wi, const Vec3& wo) const { return specular_part(wi, wo) + diffuse_part(wi, wo); }
  Rgb specular_part(const Vec3& wi, const Vec3& wo) const;
  Rgb diffuse_part(const Vec3& wi, const Vec3& wo) const;
  void validate() const;
  /// c(n) above.
  static double normalisation(double exponent);
};

/// Any of the analytic models.
using AnalyticBrdf = std::variant<Lambertian, GgxConductor, RoughPlastic, BlinnPhong>;

/// f(wi, wo) of whichever model `brdf` holds.
Rgb evaluate(const AnalyticBrdf& brdf, const Vec3& wi, const Vec3& wo);

/// Throws matlas::Error if the parameters are outside the documented ranges.
void validate(const AnalyticBrdf& brdf);

/// Family name used in file names: "lambert", "ggx", "plastic" or "phong".
std::string family_name(const AnalyticBrdf& brdf);

/// One line with the model and all of its parameters, e.g.
/// "ggx f0=(1.000 0.782 0.344) alpha=0.200".
std::string describe(const AnalyticBrdf& brdf);

}  // namespace matlas
