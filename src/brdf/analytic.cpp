#include "brdf/analytic.h"

#include <cmath>
#include <cstdio>

#include "brdf/analytic_microfacet.h"
#include "core/error.h"

namespace matlas {

namespace {

bool above_horizon(const Vec3& wi, const Vec3& wo) { return wi.z() > 0.0 && wo.z() > 0.0; }

/// Unit half vector of a pair of directions above the horizon (never degenerate there).
Vec3 half_vector(const Vec3& wi, const Vec3& wo) { return (wi + wo).normalized(); }

/// D G2 / (4 cos_i cos_o): the GGX specular lobe without Fresnel. Also returns cos(wi, h).
double ggx_lobe(const Vec3& wi, const Vec3& wo, double alpha, double* cos_d) {
  const Vec3 h = half_vector(wi, wo);
  *cos_d = std::max(0.0, wi.dot(h));
  const double d = microfacet::ggx_d(h.z(), alpha);
  const double g = microfacet::smith_g2_height_correlated(wi.z(), wo.z(), alpha);
  return d * g / (4.0 * wi.z() * wo.z());
}

void check_unit_range(const Rgb& v, const char* model, const char* name) {
  for (int c = 0; c < 3; ++c) {
    if (!(v[c] >= 0.0 && v[c] <= 1.0))
      throw Error(std::string(model) + ": " + name + " must be in [0, 1] per channel, got " +
                  std::to_string(v[c]));
  }
}

void check_alpha(double alpha, const char* model) {
  if (!(alpha >= microfacet::kMinAlpha && alpha <= 1.0))
    throw Error(std::string(model) + ": alpha must be in [" + std::to_string(microfacet::kMinAlpha) +
                ", 1], got " + std::to_string(alpha));
}

std::string rgb_text(const Rgb& c) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.3f %.3f %.3f)", c[0], c[1], c[2]);
  return buf;
}

std::string number(const char* format, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

// --- Lambertian ---------------------------------------------------------------------------------

Rgb Lambertian::operator()(const Vec3& wi, const Vec3& wo) const {
  return above_horizon(wi, wo) ? Rgb(albedo / kPi) : Rgb(Rgb::Zero());
}

void Lambertian::validate() const { check_unit_range(albedo, "lambert", "albedo"); }

// --- GGX conductor ------------------------------------------------------------------------------

Rgb GgxConductor::operator()(const Vec3& wi, const Vec3& wo) const {
  if (!above_horizon(wi, wo)) return Rgb::Zero();
  double cos_d = 0.0;
  const double lobe = ggx_lobe(wi, wo, alpha, &cos_d);
  return lobe * microfacet::fresnel_schlick(f0, cos_d);
}

void GgxConductor::validate() const {
  check_unit_range(f0, "ggx", "f0");
  check_alpha(alpha, "ggx");
}

// --- Rough plastic ------------------------------------------------------------------------------

Rgb RoughPlastic::specular_part(const Vec3& wi, const Vec3& wo) const {
  if (!above_horizon(wi, wo)) return Rgb::Zero();
  double cos_d = 0.0;
  const double lobe = ggx_lobe(wi, wo, alpha, &cos_d);
  return Rgb::Constant(specular * lobe * microfacet::fresnel_dielectric(cos_d, ior));
}

Rgb RoughPlastic::diffuse_part(const Vec3& wi, const Vec3& wo) const {
  if (!above_horizon(wi, wo)) return Rgb::Zero();
  const double ti = 1.0 - specular * microfacet::fresnel_dielectric(wi.z(), ior);
  const double to = 1.0 - specular * microfacet::fresnel_dielectric(wo.z(), ior);
  return diffuse * (ti * to / kPi);
}

void RoughPlastic::validate() const {
  check_unit_range(diffuse, "plastic", "diffuse");
  check_alpha(alpha, "plastic");
  if (!(ior >= 1.0 && ior <= 2.0))
    throw Error("plastic: ior must be in [1, 2], got " + std::to_string(ior));
  if (!(specular >= 0.0 && specular <= 1.0))
    throw Error("plastic: specular must be in [0, 1], got " + std::to_string(specular));
}

// --- Blinn-Phong --------------------------------------------------------------------------------

double BlinnPhong::normalisation(double n) {
  return (n + 2.0) * (n + 4.0) / (8.0 * kPi * (std::exp2(-0.5 * n) + n));
}

Rgb BlinnPhong::specular_part(const Vec3& wi, const Vec3& wo) const {
  if (!above_horizon(wi, wo)) return Rgb::Zero();
  const double cos_h = half_vector(wi, wo).z();
  return specular * (normalisation(exponent) * std::pow(std::max(0.0, cos_h), exponent));
}

Rgb BlinnPhong::diffuse_part(const Vec3& wi, const Vec3& wo) const {
  return above_horizon(wi, wo) ? Rgb(diffuse / kPi) : Rgb(Rgb::Zero());
}

void BlinnPhong::validate() const {
  check_unit_range(specular, "phong", "specular");
  check_unit_range(diffuse, "phong", "diffuse");
  check_unit_range(specular + diffuse, "phong", "specular + diffuse");
  if (!(exponent >= 0.0 && exponent <= 1e6))
    throw Error("phong: exponent must be in [0, 1e6], got " + std::to_string(exponent));
}

// --- The variant --------------------------------------------------------------------------------

Rgb evaluate(const AnalyticBrdf& brdf, const Vec3& wi, const Vec3& wo) {
  return std::visit([&](const auto& f) { return Rgb(f(wi, wo)); }, brdf);
}

void validate(const AnalyticBrdf& brdf) {
  std::visit([](const auto& f) { f.validate(); }, brdf);
}

std::string family_name(const AnalyticBrdf& brdf) {
  struct Name {
    std::string operator()(const Lambertian&) const { return "lambert"; }
    std::string operator()(const GgxConductor&) const { return "ggx"; }
    std::string operator()(const RoughPlastic&) const { return "plastic"; }
    std::string operator()(const BlinnPhong&) const { return "phong"; }
  };
  return std::visit(Name{}, brdf);
}

std::string describe(const AnalyticBrdf& brdf) {
  struct Describe {
    std::string operator()(const Lambertian& f) const { return "lambert albedo=" + rgb_text(f.albedo); }
    std::string operator()(const GgxConductor& f) const {
      return "ggx f0=" + rgb_text(f.f0) + " alpha=" + number("%.3f", f.alpha);
    }
    std::string operator()(const RoughPlastic& f) const {
      return "plastic diffuse=" + rgb_text(f.diffuse) + " alpha=" + number("%.3f", f.alpha) +
             " ior=" + number("%.3f", f.ior) + " specular=" + number("%.3f", f.specular);
    }
    std::string operator()(const BlinnPhong& f) const {
      return "phong specular=" + rgb_text(f.specular) + " n=" + number("%g", f.exponent) +
             " diffuse=" + rgb_text(f.diffuse);
    }
  };
  return std::visit(Describe{}, brdf);
}

}  // namespace matlas
