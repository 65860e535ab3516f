#pragma once
// Blender's Principled BSDF before 4.0 (Blender 2.8-3.6, "Principled v1"), as Cycles evaluates it
// for an opaque, isotropic surface with the "GGX" distribution (Cycles 3.4's svm/closure.h and
// closure/bsdf_principled_diffuse.h, bsdf_principled_sheen.h, bsdf_microfacet.h): Disney's 2012
// BRDF with Cycles' own choices. `matlas fit --model principled-v1` fits it, so that the
// material a Blender 2.8-3.6 user gets from the fit's script is the one matlas fitted and renders
// (docs/EXPORT.md, "In Blender").
//
//   f = (1 - metallic) (diffuse + sheen) + specular_lobe + coat
//   diffuse = base / pi [(1 - FV/2)(1 - FL/2) + RR (FL + FV + FL FV (RR - 1))]
//             FL = (1 - cos_i)^5, FV = (1 - cos_o)^5, RR = roughness (1 + wi.wo) = 2 roughness cos_d^2
//   sheen   = sheen ((1 - sheen_tint) + sheen_tint base / Y709(base)) (1 - cos_d)^5     (no 1/pi)
//   specular_lobe = F D G1(wi) G1(wo) / (4 cos_i cos_o), GGX with alpha = roughness^2 and
//             separable Smith masking, F = cspec0 (1 - FH) + FH (the exact dielectric Fresnel
//             rescaled, FH = (F_ior(cos_d) - F_ior(1)) / (1 - F_ior(1))),
//             ior = 2 / (1 - sqrt(0.08 specular)) - 1,
//             cspec0 = 0.08 specular ((1 - specular_tint) + specular_tint base / (0.3, 0.6, 0.1).base)
//                      (1 - metallic) + metallic base
//   coat    = coat x the specular lobe of a black dielectric of "Specular" 0.5 (F0 0.04, IOR 1.5)
//             and roughness coat_roughness: a second Principled BSDF, mixed in at weight `coat`
//             and added (Blender's Mix and Add shaders).
// The coat is not the Principled BSDF's own "Clearcoat" (Disney's GTR1 lobe at a quarter weight):
// Cycles 2.8-3.6 draws that lobe's samples from GGX but weighs them by GTR1's density, so that it
// renders brighter than its BRDF (by 10 % on a coat alone of roughness 0.3 and 84 % at 0.075,
// bench/blender_check.sh), by an amount that depends on the lighting: no table can match it.
// Lobes Cycles leaves out are left out here: the specular when specular and metallic are both at
// most 1e-5, the sheen and coat at weights of at most 1e-5, and any GGX lobe whose alpha^2 is at
// most 1e-7 (Cycles treats it as a mirror, which a table cannot hold). Reciprocal and isotropic,
// 0 at or below the horizon; single scattering (the "Multiscatter GGX" distribution adds energy
// that this model does not have).
#include "brdf/gltf_pbr.h"
#include "brdf/types.h"

namespace matlas {

struct PrincipledV1 {
  Rgb base_color = Rgb::Constant(0.8);   ///< "Base Color" (linear RGB), in [0, 1]
  double metallic = 0.0;                 ///< "Metallic", in [0, 1]
  double specular = 0.5;                 ///< "Specular", in [0, 1] (0.5: F0 = 0.04)
  double specular_tint = 0.0;            ///< "Specular Tint", in [0, 1]
  double roughness = 0.5;                ///< "Roughness" r (alpha = r^2), in [0, 1]
  double sheen = 0.0;                    ///< "Sheen", in [0, 1]
  double sheen_tint = 0.5;               ///< "Sheen Tint", in [0, 1]
  double coat = 0.0;                     ///< the coat's weight (its Mix Shader's factor), in [0, 1]
  double coat_roughness = 0.03;          ///< the coat's "Roughness" (alpha = r^2), in [0, 1]

  Rgb operator()(const Vec3& wi, const Vec3& wo) const;
  /// f at precomputed cosines (cos_i, cos_o > 0).
  Rgb evaluate(const PbrCosines& c) const;
  /// Throws matlas::Error naming the parameter outside its range.
  void validate() const;
};

}  // namespace matlas
