#include "pathtrace/surface.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
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
  MATLAS_DCHECK(ps >= 0 && ps <= 1, "a probability");
  *wi = u0 < ps ? render::sample_ggx_reflection(wo, s.alpha, u1, u2) : render::sample_cosine(u1, u2);
  if (wi->z() <= 0) return 0.0;
  return surface_pdf(s, wo, *wi);
}

double surface_pdf(const SurfaceSpec& s, const Vec3& wo, const Vec3& wi) {
  const double ps = specular_probability(s);
  double p = (1.0 - ps) * render::cosine_pdf(wi);
  if (ps > 0) p += ps * render::ggx_reflection_pdf(wo, wi, s.alpha);
  MATLAS_DCHECK(p >= 0, "a mixture of densities");
  return p;
}

}  // namespace matlas::pathtrace
