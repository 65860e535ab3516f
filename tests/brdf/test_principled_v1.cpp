// Blender 2.8-3.6's Principled BSDF (Cycles' Principled v1) against closed forms written out from
// Cycles 3.4's closures: the Burley diffuse with its retro-reflection, the Disney sheen, the GGX
// lobe with separable Smith masking and the rescaled dielectric Fresnel, and the coat layer.
#include <cmath>

#include <gtest/gtest.h>

#include "brdf/principled_v1.h"
#include "support/error_of.h"

namespace matlas {
namespace {
namespace principled_v1_tests {

Vec3 direction(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

double pow5(double x) { return x * x * x * x * x; }

/// The GGX terms written out: D(h) = alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2), G1 = 2 / (1 + sqrt(1
/// + alpha^2 tan^2)).
double ggx(double cos_h, double alpha) {
  const double c2 = cos_h * cos_h, t2 = (1 - c2) / c2, a2 = alpha * alpha;
  return a2 / (kPi * c2 * c2 * (a2 + t2) * (a2 + t2));
}
double g1(double cos_t, double alpha) {
  const double t2 = (1 - cos_t * cos_t) / (cos_t * cos_t);
  return 2 / (1 + std::sqrt(1 + alpha * alpha * t2));
}

TEST(PrincipledV1, WithoutSpecularItIsBurleysDiffuseWithItsRetroReflection) {
  PrincipledV1 m;
  m.base_color = Rgb(0.7, 0.4, 0.2);
  m.specular = 0.0;
  m.roughness = 0.6;
  const Vec3 wi = direction(50, 0), wo = direction(30, 140);
  const Vec3 h = (wi + wo).normalized();
  const double fl = pow5(1 - wi.z()), fv = pow5(1 - wo.z()), rr = 0.6 * (1 + wi.dot(wo));
  const double shape = (1 - 0.5 * fl) * (1 - 0.5 * fv) + rr * (fl + fv + fl * fv * (rr - 1));
  // The retro term by its own definition: RR = 2 r (wi.h)^2.
  EXPECT_NEAR(rr, 2 * 0.6 * wi.dot(h) * wi.dot(h), 1e-12);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m(wi, wo)[c], m.base_color[c] / kPi * shape, 1e-12);
  // At normal incidence both Schlick weights vanish: the plain Lambertian value.
  const Vec3 n(0, 0, 1);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m(n, n)[c], m.base_color[c] / kPi, 1e-12);
}

TEST(PrincipledV1, AtNormalIncidenceTheSpecularIsItsF0TimesTheGgxPeak) {
  // wi = wo = n: D = 1 / (pi alpha^2), G1 = 1, F = cspec0 = 0.08 specular; the diffuse is base / pi.
  PrincipledV1 m;
  m.base_color = Rgb(0.2, 0.4, 0.6);
  m.specular = 0.5;
  m.roughness = 0.4;
  const double alpha = 0.16;
  const Vec3 n(0, 0, 1);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(m(n, n)[c], m.base_color[c] / kPi + 0.04 / (4 * kPi * alpha * alpha), 1e-9);
}

TEST(PrincipledV1, AMetalIsTheGgxLobeWithSeparableMaskingAndItsBaseColourAsF0) {
  // Metallic 1, specular 0: the Fresnel's IOR is 1, so F is the base colour at every angle.
  PrincipledV1 m;
  m.base_color = Rgb(0.9, 0.6, 0.3);
  m.metallic = 1.0;
  m.specular = 0.0;
  m.roughness = 0.5;
  const double alpha = 0.25;
  for (const auto& [wi, wo] : {std::pair{direction(10, 0), direction(20, 180)}, std::pair{direction(60, 30), direction(45, 200)},
                               std::pair{direction(80, 0), direction(75, 170)}}) {
    const Vec3 h = (wi + wo).normalized();
    const double lobe = ggx(h.z(), alpha) * g1(wi.z(), alpha) * g1(wo.z(), alpha) / (4 * wi.z() * wo.z());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m(wi, wo)[c], m.base_color[c] * lobe, 1e-9 * (1 + lobe));
  }
}

TEST(PrincipledV1, TheSpecularFresnelRisesFromF0ToWhiteAtGrazing) {
  // Dielectric, specular 0.5 (IOR 1.5, F0 0.04): F = 0.04 (1 - FH) + FH with FH the exact Fresnel
  // rescaled; at wi.h = 0.5 the exact Fresnel of IOR 1.5 is 0.0891...; tinted specular is the
  // base's hue, here grey so the tint changes nothing.
  PrincipledV1 m;
  m.base_color = Rgb::Constant(0.0);
  m.specular = 0.5;
  m.roughness = 0.3;
  const double alpha = 0.09;
  const Vec3 wi = direction(60, 0), wo = direction(60, 180);  // h = n, wi.h = 0.5
  const double ci = 0.5, ct = std::sqrt(1 - (1 - ci * ci) / 2.25);
  const double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct), rp = (1.5 * ci - ct) / (1.5 * ci + ct);
  const double exact = 0.5 * (rs * rs + rp * rp), fh = (exact - 0.04) / 0.96;
  const double lobe = ggx(1.0, alpha) * g1(0.5, alpha) * g1(0.5, alpha) / (4 * 0.25);
  EXPECT_NEAR(m(wi, wo)[0], (0.04 * (1 - fh) + fh) * lobe, 1e-9 * lobe);
  m.base_color = Rgb::Constant(0.5);
  m.specular_tint = 1.0;
  PrincipledV1 untinted = m;
  untinted.specular_tint = 0.0;
  EXPECT_NEAR(m(wi, wo)[1], untinted(wi, wo)[1], 1e-12);
}

TEST(PrincipledV1, TheSheenAddsItsTintedSchlickWeightWithoutOneOverPi) {
  PrincipledV1 plain;
  plain.base_color = Rgb(0.6, 0.3, 0.1);
  plain.roughness = 0.8;
  PrincipledV1 sheened = plain;
  sheened.sheen = 0.7;
  sheened.sheen_tint = 0.4;
  const Vec3 wi = direction(75, 0), wo = direction(70, 60);
  const double fd = pow5(1 - wi.dot((wi + wo).normalized()));
  const double y = 0.2126 * 0.6 + 0.7152 * 0.3 + 0.0722 * 0.1;
  for (int c = 0; c < 3; ++c) {
    const double colour = 0.6 + 0.4 * plain.base_color[c] / y;
    EXPECT_NEAR(sheened(wi, wo)[c] - plain(wi, wo)[c], 0.7 * colour * fd, 1e-12);
  }
  // A metal has no diffuse, so no sheen.
  plain.metallic = sheened.metallic = 1.0;
  EXPECT_EQ((sheened(wi, wo) - plain(wi, wo)).abs().maxCoeff(), 0.0);
}

TEST(PrincipledV1, TheCoatIsABlackDielectricLobeOfF0004AtItsWeight) {
  // wi = wo = n: the coat adds coat 0.04 / (4 pi alpha^2); at wi.h = cos 70 deg its Fresnel is the
  // rescaled exact Fresnel of IOR 1.5, its masking that of its own alpha.
  PrincipledV1 base;
  base.base_color = Rgb::Constant(0.1);
  base.specular = 0.0;
  PrincipledV1 coated = base;
  coated.coat = 0.8;
  coated.coat_roughness = 0.2;
  const double alpha = 0.04;
  const Vec3 n(0, 0, 1);
  EXPECT_NEAR(coated(n, n)[0] - base(n, n)[0], 0.8 * 0.04 / (4 * kPi * alpha * alpha), 1e-9);
  const Vec3 wi = direction(70, 0), wo = direction(70, 180);  // h = n, wi.h = cos 70
  const double ci = std::cos(70 * kPi / 180), ct = std::sqrt(1 - (1 - ci * ci) / 2.25);
  const double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct), rp = (1.5 * ci - ct) / (1.5 * ci + ct);
  const double fh = (0.5 * (rs * rs + rp * rp) - 0.04) / 0.96;
  const double expected = 0.8 * (0.04 * (1 - fh) + fh) * ggx(1.0, alpha) * g1(ci, alpha) * g1(ci, alpha) / (4 * ci * ci);
  EXPECT_NEAR(coated(wi, wo)[0] - base(wi, wo)[0], expected, 1e-9 * expected);
}

TEST(PrincipledV1, IsReciprocalZeroBelowTheHorizonAndDropsMirrorLobesAsCyclesDoes) {
  PrincipledV1 m;
  m.base_color = Rgb(0.3, 0.6, 0.9);
  m.metallic = 0.3;
  m.roughness = 0.25;
  m.sheen = 0.5;
  m.coat = 0.5;
  m.coat_roughness = 0.1;
  for (const auto& [wi, wo] : {std::pair{direction(10, 0), direction(20, 180)}, std::pair{direction(70, 10), direction(5, 90)}})
    EXPECT_LT((m(wi, wo) - m(wo, wi)).abs().maxCoeff(), 1e-12);
  EXPECT_EQ(m(direction(30, 0), Vec3(0.5, 0, -0.86)).maxCoeff(), 0.0);
  // Roughness 0.01: alpha^2 = 1e-8, a mirror in Cycles (sampled, never evaluated): only the
  // diffuse is left, as with no specular at all.
  PrincipledV1 mirror = m, none = m;
  mirror.roughness = none.roughness = 0.01;
  none.specular = 0.0;
  none.metallic = 1e-6;
  mirror.coat = none.coat = 0.0;
  mirror.metallic = 1e-6;
  const Vec3 n(0, 0, 1);
  EXPECT_NEAR(mirror(n, n)[0], none(n, n)[0], 1e-12);
}

TEST(PrincipledV1, AParameterOutsideItsRangeIsNamed) {
  PrincipledV1 m;
  m.sheen_tint = 1.5;
  EXPECT_EQ(test::error_of([&] { m.validate(); }), "principled-v1: sheen_tint must be in [0, 1], got 1.500000");
  EXPECT_EQ(test::error_of([] { PrincipledV1{}.validate(); }), "no error");
}

}  // namespace principled_v1_tests
}  // namespace
}  // namespace matlas
