#include "brdf/gltf_pbr.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "brdf/analytic_microfacet.h"
#include "core/error.h"

namespace matlas {

PbrCosines pbr_cosines(const Vec3& wi, const Vec3& wo) {
  const Vec3 h = (wi + wo).normalized();
  return {wi.z(), wo.z(), h.z(), std::max(0.0, wi.dot(h))};
}

double GltfPbr::alpha() const { return std::max(roughness * roughness, microfacet::kMinAlpha); }

Rgb GltfPbr::evaluate(const PbrCosines& c) const {
  const double a = alpha();
  const double lobe = microfacet::ggx_d(c.cos_h, a) *
                      microfacet::smith_g2_height_correlated(c.cos_i, c.cos_o, a) / (4.0 * c.cos_i * c.cos_o);
  const double m = 1.0 - c.cos_d, m2 = m * m, schlick = m2 * m2 * m;
  const double f0 = microfacet::dielectric_f0(ior);
  const double fd = specular * (f0 + (1.0 - f0) * schlick);
  const Rgb dielectric = (1.0 - fd) * base_color / kPi + fd * lobe;
  const Rgb conductor = (base_color + (1.0 - base_color) * schlick) * lobe;
  return (1.0 - metallic) * dielectric + metallic * conductor;
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
  if (!(ior >= 1.0 && ior <= 3.0)) throw Error("gltf: ior must be in [1, 3], got " + std::to_string(ior));
}

std::string describe(const GltfPbr& m) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "gltf base=(%.3f %.3f %.3f) metallic=%.3f roughness=%.3f specular=%.3f",
                m.base_color[0], m.base_color[1], m.base_color[2], m.metallic, m.roughness, m.specular);
  return buf;
}

}  // namespace matlas
