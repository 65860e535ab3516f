#include "brdf/principled_v1.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "brdf/analytic_microfacet.h"
#include "core/error.h"

namespace matlas {

namespace {

/// Cycles' CLOSURE_WEIGHT_CUTOFF: lobes of smaller weight are not created.
constexpr double kWeightCutoff = 1e-5;
/// Cycles evaluates no GGX lobe with alpha_x alpha_y at most this (a mirror, sampled only).
constexpr double kMirrorAlpha2 = 1e-7;

double schlick_weight(double cos) {
  const double m = std::clamp(1.0 - cos, 0.0, 1.0), m2 = m * m;
  return m2 * m2 * m;
}

/// Cycles' interpolate_fresnel_color: cspec0 blended to white by the exact dielectric Fresnel at
/// cos_d, rescaled to run from 0 at normal incidence to 1 at grazing.
Rgb interpolated_fresnel(const Rgb& cspec0, double cos_d, double ior) {
  const double f0 = microfacet::fresnel_dielectric(1.0, ior);
  const double fh = (microfacet::fresnel_dielectric(cos_d, ior) - f0) / (1.0 - f0);
  return cspec0 * (1.0 - fh) + fh;
}

/// The Principled BSDF's GGX lobe: F D G1(wi) G1(wo) / (4 cos_i cos_o), 0 for a mirror-like alpha.
Rgb specular_lobe(const PbrCosines& c, const Rgb& cspec0, double specular, double roughness) {
  const double alpha = std::min(roughness * roughness, 1.0);
  if (alpha * alpha <= kMirrorAlpha2) return Rgb::Zero();
  const double ior = 2.0 / (1.0 - std::sqrt(0.08 * specular)) - 1.0;
  const double lobe = microfacet::ggx_d(c.cos_h, alpha) * microfacet::smith_g1(c.cos_i, alpha) *
                      microfacet::smith_g1(c.cos_o, alpha) / (4.0 * c.cos_i * c.cos_o);
  return interpolated_fresnel(cspec0, c.cos_d, ior) * lobe;
}

}  // namespace

Rgb PrincipledV1::evaluate(const PbrCosines& c) const {
  const double fl = schlick_weight(c.cos_i), fv = schlick_weight(c.cos_o), fd = schlick_weight(c.cos_d);
  const double diffuse_weight = 1.0 - std::clamp(metallic, 0.0, 1.0);
  Rgb f = Rgb::Zero();
  if (diffuse_weight > kWeightCutoff) {
    const double rr = roughness * 2.0 * c.cos_d * c.cos_d;
    const double shape = (1.0 - 0.5 * fv) * (1.0 - 0.5 * fl) + rr * (fl + fv + fl * fv * (rr - 1.0));
    f += diffuse_weight * base_color * (shape / kPi);
    if (sheen > kWeightCutoff) {
      const double y = 0.2126 * base_color[0] + 0.7152 * base_color[1] + 0.0722 * base_color[2];
      const Rgb hue = y > 0.0 ? Rgb(base_color / y) : Rgb::Ones();
      f += diffuse_weight * sheen * ((1.0 - sheen_tint) + sheen_tint * hue) * fd;
    }
  }
  if (specular > kWeightCutoff || metallic > kWeightCutoff) {
    const double y = 0.3 * base_color[0] + 0.6 * base_color[1] + 0.1 * base_color[2];
    const Rgb hue = y > 0.0 ? Rgb(base_color / y) : Rgb::Ones();
    const Rgb tint = (1.0 - specular_tint) + specular_tint * hue;
    const Rgb cspec0 = (specular * 0.08 * tint * (1.0 - metallic) + base_color * metallic).cwiseMax(0.0).cwiseMin(1.0);
    f += specular_lobe(c, cspec0, specular, roughness);
  }
  if (coat > kWeightCutoff) {
    constexpr double kCoatSpecular = 0.5;  // F0 = 0.04, IOR 1.5
    f += coat * specular_lobe(c, Rgb::Constant(0.08 * kCoatSpecular), kCoatSpecular, coat_roughness);
  }
  return f;
}

Rgb PrincipledV1::operator()(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
  return evaluate(pbr_cosines(wi, wo));
}

void PrincipledV1::validate() const {
  const auto check = [](double v, const char* name) {
    if (!(v >= 0.0 && v <= 1.0))
      throw Error(std::string("principled-v1: ") + name + " must be in [0, 1], got " + std::to_string(v));
  };
  for (int c = 0; c < 3; ++c) check(base_color[c], "base_color");
  check(metallic, "metallic");
  check(specular, "specular");
  check(specular_tint, "specular_tint");
  check(roughness, "roughness");
  check(sheen, "sheen");
  check(sheen_tint, "sheen_tint");
  check(coat, "coat");
  check(coat_roughness, "coat_roughness");
}

}  // namespace matlas
