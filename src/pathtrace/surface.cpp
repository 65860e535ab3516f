#include "pathtrace/surface.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "render/sampling.h"

namespace matlas::pathtrace {

namespace {

double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

double lambda(const Vec3& w, double alpha) {
  const double c2 = w.z() * w.z();
  const double t2 = std::max(0.0, 1.0 - c2) / std::max(c2, 1e-300);
  return 0.5 * (std::sqrt(1.0 + alpha * alpha * t2) - 1.0);
}

/// Probability of the GGX lobe in the surface's sampling mixture.
double specular_probability(const SurfaceSpec& s) {
  if (s.kind == SurfaceSpec::Kind::lambert) return 0.0;
  const double ks = luminance(s.specular), kd = luminance(s.albedo);
  return std::clamp(ks / std::max(ks + kd, 1e-12), 0.25, 0.9);
}

}  // namespace

double ggx_d(double cos_h, double alpha) {
  if (cos_h <= 0) return 0.0;
  const double a2 = alpha * alpha;
  const double d = cos_h * cos_h * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}

double ggx_g2(const Vec3& wi, const Vec3& wo, double alpha) {
  return 1.0 / (1.0 + lambda(wi, alpha) + lambda(wo, alpha));
}

Rgb surface_eval(const SurfaceSpec& s, const Vec3& wi, const Vec3& wo) {
  if (wi.z() <= 0 || wo.z() <= 0) return Rgb::Zero();
  Rgb f = s.albedo / kPi;
  if (s.kind == SurfaceSpec::Kind::ggx) {
    const Vec3 h = (wi + wo).normalized();
    const double c = std::max(0.0, wi.dot(h));
    const Rgb fresnel = s.specular + (1.0 - s.specular) * std::pow(1.0 - c, 5.0);
    f += fresnel * (ggx_d(h.z(), s.alpha) * ggx_g2(wi, wo, s.alpha) / (4.0 * wi.z() * wo.z()));
  }
  return f;
}

double surface_sample(const SurfaceSpec& s, const Vec3& wo, double u0, double u1, double u2, Vec3* wi) {
  const double ps = specular_probability(s);
  *wi = u0 < ps ? render::sample_ggx_reflection(wo, s.alpha, u1, u2) : render::sample_cosine(u1, u2);
  if (wi->z() <= 0) return 0.0;
  return surface_pdf(s, wo, *wi);
}

double surface_pdf(const SurfaceSpec& s, const Vec3& wo, const Vec3& wi) {
  const double ps = specular_probability(s);
  double p = (1.0 - ps) * render::cosine_pdf(wi);
  if (ps > 0) p += ps * render::ggx_reflection_pdf(wo, wi, s.alpha);
  return p;
}

double FixedDensity::sample(const Vec3& wo, double u0, double u1, double u2, Vec3* wi) const {
  double total = cosine;
  for (const auto& l : lobes) total += l.second;
  double pick = u0 * total - cosine;
  if (pick < 0) {
    *wi = render::sample_cosine(u1, u2);
  } else {
    std::size_t k = 0;
    while (k + 1 < lobes.size() && pick >= lobes[k].second) pick -= lobes[k++].second;
    *wi = render::sample_ggx_reflection(wo, lobes[k].first, u1, u2);
  }
  if (wi->z() <= 0) return 0.0;
  return pdf(wo, *wi);
}

double FixedDensity::pdf(const Vec3& wo, const Vec3& wi) const {
  double total = cosine, p = cosine * render::cosine_pdf(wi);
  for (const auto& [alpha, weight] : lobes) {
    total += weight;
    p += weight * render::ggx_reflection_pdf(wo, wi, alpha);
  }
  return p / total;
}

void FixedDensity::validate() const {
  double total = cosine;
  if (cosine < 0) throw Error("fixed density: negative cosine probability");
  for (const auto& [alpha, weight] : lobes) {
    if (!(alpha > 0 && alpha <= 1)) throw Error("fixed density: lobe alpha must be in (0, 1]");
    if (weight < 0) throw Error("fixed density: negative lobe probability");
    total += weight;
  }
  if (!(total > 0)) throw Error("fixed density: all probabilities are zero");
}

}  // namespace matlas::pathtrace
