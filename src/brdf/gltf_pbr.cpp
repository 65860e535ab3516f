#include "brdf/gltf_pbr.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "brdf/analytic_microfacet.h"
#include "core/error.h"

namespace matlas {

PbrCosines pbr_cosines(const Vec3& wi, const Vec3& wo) {
  const Vec3 h = (wi + wo).normalized();
  return {wi.z(), wo.z(), h.z(), std::max(0.0, wi.dot(h))};
}

namespace {

/// D G2 / (4 cos_i cos_o): the GGX lobe without Fresnel.
double pbr_lobe(const PbrCosines& c, double alpha) {
  return microfacet::ggx_d(c.cos_h, alpha) * microfacet::smith_g2_height_correlated(c.cos_i, c.cos_o, alpha) /
         (4.0 * c.cos_i * c.cos_o);
}

}  // namespace

double GltfPbr::alpha() const { return std::max(roughness * roughness, microfacet::kMinAlpha); }
double GltfPbr::clearcoat_alpha() const {
  return std::max(clearcoat_roughness * clearcoat_roughness, microfacet::kMinAlpha);
}

Rgb GltfPbr::evaluate(const PbrCosines& c) const {
  const double lobe = pbr_lobe(c, alpha());
  const double m = 1.0 - c.cos_d, m2 = m * m, schlick = m2 * m2 * m;
  const double f0 = microfacet::dielectric_f0(ior);
  const double fd = specular * (f0 + (1.0 - f0) * schlick);
  const Rgb dielectric = (1.0 - fd) * base_color / kPi + fd * lobe;
  const Rgb conductor = (base_color + (1.0 - base_color) * schlick) * lobe;
  const Rgb material = (1.0 - metallic) * dielectric + metallic * conductor;
  if (clearcoat <= 0.0) return material;
  constexpr double kCoatF0 = 0.04;  // IOR 1.5
  const double fc = clearcoat * (kCoatF0 + (1.0 - kCoatF0) * schlick);
  return (1.0 - fc) * material + fc * pbr_lobe(c, clearcoat_alpha());
}

Rgb GltfPbr::operator()(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
  return evaluate(pbr_cosines(wi, wo));
}

void GltfPbr::validate() const {
  const auto check = [](double v, const char* name) {
    if (!(v >= 0.0 && v <= 1.0)) throw Error(std::string("gltf: ") + name + " must be in [0, 1], got " + std::to_string(v));
  };
  for (int c = 0; c < 3; ++c) check(base_color[c], "base_color");
  check(metallic, "metallic");
  check(roughness, "roughness");
  check(specular, "specular");
  check(clearcoat, "clearcoat");
  check(clearcoat_roughness, "clearcoat_roughness");
  if (!(ior >= 1.0 && ior <= 3.0)) throw Error("gltf: ior must be in [1, 3], got " + std::to_string(ior));
}

}  // namespace matlas
