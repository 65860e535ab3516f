#include "brdf/gltf_pbr.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brdf/analytic_microfacet.h"
#include "core/error.h"
#include "core/parallel.h"

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

/// The extension's fit of the Charlie sheen's Lambda exponent, l(x, a).
double sheen_l(double x, double a) {
  const double t = (1.0 - a) * (1.0 - a);
  const auto mix = [t](double u, double v) { return u + (v - u) * t; };
  return mix(21.5473, 25.3245) / (1.0 + mix(3.82987, 3.32435) * std::pow(x, mix(0.19823, 0.16801))) +
         mix(-1.97760, -1.27393) * x + mix(-4.32054, -4.85967);
}

double sheen_lambda(double cos_theta, double a) {
  return cos_theta < 0.5 ? std::exp(sheen_l(cos_theta, a)) : std::exp(2.0 * sheen_l(0.5, a) - sheen_l(1.0 - cos_theta, a));
}

constexpr int kSheenTable = 33;

/// E on a grid: cos_theta = k / 32 (k >= 1; k = 0 copies k = 1), a = kMin + (1 - kMin) j / 32.
std::vector<double> sheen_albedo_table() {
  std::vector<double> t(kSheenTable * kSheenTable, 0.0);
  constexpr int rows = 96, columns = 96;  // midpoint rule over the hemisphere, phi in [0, pi) (even)
  // One roughness per task (1.1 s on one core for the whole table: at a fit's first evaluation).
  parallel_for_each(0, kSheenTable, [&](std::size_t row) {
    const int j = static_cast<int>(row);
    const double a = GltfPbr::kMinSheenRoughness + (1.0 - GltfPbr::kMinSheenRoughness) * j / (kSheenTable - 1);
    for (int k = 1; k < kSheenTable; ++k) {
      const double mu = static_cast<double>(k) / (kSheenTable - 1);
      const Vec3 wo(std::sqrt(1.0 - mu * mu), 0.0, mu);
      double sum = 0.0;
      for (int r = 0; r < rows; ++r) {
        const double theta = (r + 0.5) * (kPi / 2) / rows, st = std::sin(theta), ct = std::cos(theta);
        for (int c = 0; c < columns; ++c) {
          const double phi = (c + 0.5) * kPi / columns;
          const Vec3 wi(st * std::cos(phi), st * std::sin(phi), ct);
          sum += sheen_lobe(pbr_cosines(wi, wo), a) * ct * st;
        }
      }
      t[static_cast<std::size_t>(j * kSheenTable + k)] = 2.0 * sum * (kPi / 2 / rows) * (kPi / columns);
    }
    t[static_cast<std::size_t>(j * kSheenTable)] = t[static_cast<std::size_t>(j * kSheenTable + 1)];
  });
  return t;
}

}  // namespace

double sheen_lobe(const PbrCosines& c, double a) {
  const double sin2 = std::max(0.0, 1.0 - c.cos_h * c.cos_h);
  const double d = (2.0 + 1.0 / a) * std::pow(sin2, 0.5 / a) / (2.0 * kPi);
  const double v = 1.0 / ((1.0 + sheen_lambda(c.cos_o, a) + sheen_lambda(c.cos_i, a)) * 4.0 * c.cos_i * c.cos_o);
  return d * v;
}

double sheen_albedo(double cos_theta, double a) {
  static const std::vector<double> table = sheen_albedo_table();
  const double u = std::clamp(cos_theta, 0.0, 1.0) * (kSheenTable - 1);
  const double v = std::clamp((a - GltfPbr::kMinSheenRoughness) / (1.0 - GltfPbr::kMinSheenRoughness), 0.0, 1.0) *
                   (kSheenTable - 1);
  const int k0 = std::min(static_cast<int>(u), kSheenTable - 2), j0 = std::min(static_cast<int>(v), kSheenTable - 2);
  const double fu = u - k0, fv = v - j0;
  const auto at = [&](int j, int k) { return table[static_cast<std::size_t>(j * kSheenTable + k)]; };
  return (1 - fv) * ((1 - fu) * at(j0, k0) + fu * at(j0, k0 + 1)) + fv * ((1 - fu) * at(j0 + 1, k0) + fu * at(j0 + 1, k0 + 1));
}

double GltfPbr::sheen_alpha() const { return std::max(sheen_roughness, kMinSheenRoughness); }

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
  Rgb material = (1.0 - metallic) * dielectric + metallic * conductor;
  const double sheen = sheen_color.maxCoeff();
  if (sheen > 0.0) {
    const double a = sheen_alpha();
    const double scaling = std::min(1.0 - sheen * sheen_albedo(c.cos_o, a), 1.0 - sheen * sheen_albedo(c.cos_i, a));
    material = sheen_color * sheen_lobe(c, a) + scaling * material;
  }
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
  for (int c = 0; c < 3; ++c) check(sheen_color[c], "sheen_color");
  check(sheen_roughness, "sheen_roughness");
  if (!(ior >= 1.0 && ior <= 3.0)) throw Error("gltf: ior must be in [1, 3], got " + std::to_string(ior));
}

}  // namespace matlas
