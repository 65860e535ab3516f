#pragma once
// The glTF 2.0 metallic-roughness BRDF (glTF 2.0 specification, Appendix B) with the scalar
// specular factor of KHR_materials_specular, the sheen of KHR_materials_sheen and the coat of
// KHR_materials_clearcoat: the analytic
// model that glTF viewers, Blender's
// Principled BSDF, Autodesk Standard Surface and OpenPBR share at their core (a GGX lobe over a
// Lambertian base, or a GGX conductor). `matlas fit` fits it to tables (artist/pbr_fit.h).
//
//   f = (1 - metallic) [ (1 - F_d) base_color / pi + F_d V D ] + metallic F_m V D
//   F_d = specular (f0 + (1 - f0) (1 - |wi.h|)^5),  f0 = ((ior - 1) / (ior + 1))^2
//   F_m = base_color + (1 - base_color) (1 - |wi.h|)^5            (Schlick, coloured)
//   V D = D(h) G2(wi, wo) / (4 cos_i cos_o), GGX with alpha = roughness^2, Smith height-correlated
//   sheened = sheen_color D_s V_s + f min(1 - max(sheen_color) E(cos_o), 1 - max(sheen_color) E(cos_i))
//   D_s = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi), a = sheen_roughness (the extension's "Charlie"),
//   V_s = 1 / ((1 + L(cos_o) + L(cos_i)) 4 cos_i cos_o) with the extension's fitted L, and E the
//   sheen lobe's own directional albedo (sheen_albedo, tabulated by quadrature);
//   coated = (1 - clearcoat F_c) sheened + clearcoat F_c V_c D_c,  F_c = Schlick with f0 = 0.04
//   (IOR 1.5), V_c D_c the GGX lobe of alpha = clearcoat_roughness^2 (the coat over the sheen, as
//   the sheen extension layers them).
// The coat's Fresnel is taken at |wi.h| as the core's mix is (the extension's reference code uses
// N.V, which is the same at the coat's mirror peak, h = n): the model stays reciprocal, as tables are.
//
// As brdf/analytic.h's models: callable as f(wi, wo) -> Rgb in the local frame (normal +z), 0 at
// or below the horizon, reciprocal; single scattering (rough lobes lose some energy, as in the
// glTF reference viewer).
#include "brdf/types.h"

namespace matlas {

/// The cosines on which the model depends: of wi and wo with the normal, of the half vector h with
/// the normal, and of wi with h. Precomputed per direction pair by fits that evaluate the model
/// at the same directions for many parameter values.
struct PbrCosines {
  double cos_i = 0, cos_o = 0, cos_h = 0, cos_d = 0;
};

/// The cosines of a direction pair (wi, wo above the horizon).
PbrCosines pbr_cosines(const Vec3& wi, const Vec3& wo);

struct GltfPbr {
  Rgb base_color = Rgb::Constant(0.8);  ///< baseColorFactor (linear RGB), in [0, 1]
  double metallic = 0.0;                ///< metallicFactor, in [0, 1]
  double roughness = 0.5;               ///< roughnessFactor r (alpha = r^2), in [0, 1]
  double specular = 1.0;                ///< KHR_materials_specular's specularFactor, in [0, 1]
  double ior = 1.5;                     ///< KHR_materials_ior (1.5: the core specification's 0.04)
  double clearcoat = 0.0;               ///< KHR_materials_clearcoat's clearcoatFactor, in [0, 1]
  double clearcoat_roughness = 0.0;     ///< clearcoatRoughnessFactor (alpha = r^2), in [0, 1]
  Rgb sheen_color = Rgb::Zero();        ///< KHR_materials_sheen's sheenColorFactor, in [0, 1]
  double sheen_roughness = 0.0;         ///< sheenRoughnessFactor (a = r, at least kMinSheenRoughness), in [0, 1]

  Rgb operator()(const Vec3& wi, const Vec3& wo) const;
  /// f at precomputed cosines (cos_i, cos_o > 0).
  Rgb evaluate(const PbrCosines& c) const;
  /// The GGX widths: roughness^2 and clearcoat_roughness^2, kept at or above microfacet::kMinAlpha.
  double alpha() const;
  double clearcoat_alpha() const;
  /// The sheen's a: sheen_roughness, at least kMinSheenRoughness.
  double sheen_alpha() const;
  static constexpr double kMinSheenRoughness = 0.07;
  /// Throws matlas::Error naming the parameter outside its range.
  void validate() const;
};

/// E(cos_theta, a): the directional albedo of the sheen lobe D_s V_s alone (sheen colour 1) at a
/// view of cosine cos_theta, for a in [kMinSheenRoughness, 1]: bilinear in a table of 33 x 33
/// values computed once by quadrature (tests compare it with a direct integration).
double sheen_albedo(double cos_theta, double alpha);
/// D_s V_s (the sheen lobe for sheen colour 1) at the cosines.
double sheen_lobe(const PbrCosines& c, double alpha);

}  // namespace matlas
