// Analytic BRDFs: reciprocity, non-negativity, the horizon, and the microfacet building blocks
// against closed forms and independent integrals.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "brdf/analytic.h"
#include "brdf/analytic_albedo.h"
#include "brdf/analytic_microfacet.h"
#include "core/error.h"

namespace matlas {
namespace {

Vec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  const double z = n(rng), y = n(rng), x = n(rng);  // sequenced: argument order is unspecified
  Vec3 v(x, y, z);
  return v.normalized();
}

Vec3 random_upper(std::mt19937_64& rng) {
  Vec3 v = random_direction(rng);
  v.z() = std::abs(v.z()) + 1e-6;
  return v.normalized();
}

std::vector<AnalyticBrdf> sample_models() {
  return {
      Lambertian{Rgb(0.8, 0.5, 0.2)},
      GgxConductor{Rgb(1.0, 0.782, 0.344), 0.05},
      GgxConductor{Rgb(0.55, 0.56, 0.55), 0.6},
      RoughPlastic{Rgb(0.7, 0.05, 0.04), 0.02, 1.5, 1.0},
      RoughPlastic{Rgb(0.2, 0.4, 0.9), 0.5, 1.8, 0.7},
      BlinnPhong{Rgb::Constant(0.1), 200.0, Rgb(0.04, 0.1, 0.6)},
      BlinnPhong{Rgb::Constant(1.0), 3.0, Rgb::Zero()},
  };
}

TEST(Analytic, EveryModelIsReciprocal) {
  std::mt19937_64 rng(7);
  for (const AnalyticBrdf& brdf : sample_models()) {
    for (int n = 0; n < 2000; ++n) {
      const Vec3 a = random_upper(rng), b = random_upper(rng);
      const Rgb fab = evaluate(brdf, a, b), fba = evaluate(brdf, b, a);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(fab[c], fba[c], 1e-12 * std::max(1.0, std::abs(fab[c]))) << describe(brdf);
    }
  }
}

TEST(Analytic, EveryModelIsNonNegativeFiniteAndZeroBelowTheHorizon) {
  std::mt19937_64 rng(11);
  for (const AnalyticBrdf& brdf : sample_models()) {
    for (int n = 0; n < 4000; ++n) {
      const Vec3 a = random_direction(rng), b = random_direction(rng);
      const Rgb f = evaluate(brdf, a, b);
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(f[c])) << describe(brdf);
        ASSERT_GE(f[c], 0.0) << describe(brdf);
        if (a.z() <= 0.0 || b.z() <= 0.0) {
          ASSERT_EQ(f[c], 0.0) << describe(brdf);
        }
      }
    }
    // Exactly on the horizon, and at grazing pairs just above it.
    const Vec3 horizon(1, 0, 0), grazing = Vec3(1, 0, 1e-9).normalized();
    EXPECT_TRUE((evaluate(brdf, horizon, Vec3::UnitZ()) == 0.0).all());
    EXPECT_TRUE(evaluate(brdf, grazing, grazing).isFinite().all()) << describe(brdf);
    EXPECT_TRUE(evaluate(brdf, grazing, Vec3(-1, 0, 1e-9).normalized()).isFinite().all());
  }
}

TEST(Analytic, LambertianIsAlbedoOverPi) {
  const Lambertian f{Rgb(0.8, 0.5, 0.2)};
  const Rgb v = f(Vec3(0.3, 0.1, 0.9).normalized(), Vec3(-0.5, 0.2, 0.4).normalized());
  EXPECT_NEAR(v[0], 0.8 / kPi, 1e-15);
  EXPECT_NEAR(v[2], 0.2 / kPi, 1e-15);
}

TEST(Analytic, GgxConductorAtNormalIncidenceMatchesClosedForm) {
  // wi = wo = n: h = n, D = 1/(pi alpha^2), G2 = 1, F = F0, so f = F0 / (4 pi alpha^2).
  const GgxConductor f{Rgb(0.9, 0.6, 0.3), 0.2};
  const Rgb v = f(Vec3::UnitZ(), Vec3::UnitZ());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], f.f0[c] / (4 * kPi * 0.04), 1e-12);
}

TEST(Analytic, GgxDistributionIsNormalised) {
  // Integral of D(h) cos(theta_h) over the hemisphere = 1, by the midpoint rule in theta_h.
  for (double alpha : {0.05, 0.3, 1.0}) {
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) / n * (kPi / 2);
      sum += microfacet::ggx_d(std::cos(t), alpha) * std::cos(t) * std::sin(t);
    }
    EXPECT_NEAR(sum * 2 * kPi * (kPi / 2) / n, 1.0, 1e-4) << "alpha " << alpha;
  }
}

TEST(Analytic, SmithMaskingPassesTheWeakWhiteFurnaceTest) {
  // Heitz 2014, eq. 17: the projected area of the visible microfacets equals that of the macro
  // surface, integral of G1(wo) <wo.h>+ D(h) dh = cos(theta_o). An independent check of Lambda.
  // Midpoint rule in (theta_h, phi_h) on the exact D (the integrand is smooth there).
  const int nt = 1500, np = 360;
  for (double alpha : {0.1, 0.5, 1.0}) {
    for (double theta : {0.0, 0.8, 1.4}) {
      const Vec3 wo(std::sin(theta), 0, std::cos(theta));
      double sum = 0;
      for (int a = 0; a < nt; ++a) {
        const double t = (a + 0.5) / nt * (kPi / 2), st = std::sin(t), ct = std::cos(t);
        const double d = microfacet::ggx_d(ct, alpha) * st;
        for (int b = 0; b < np; ++b) {
          const double p = (b + 0.5) / np * 2 * kPi;
          sum += d * std::max(0.0, wo.x() * st * std::cos(p) + wo.z() * ct);
        }
      }
      const double projected = microfacet::smith_g1(wo.z(), alpha) * sum * (kPi / 2 / nt) * (2 * kPi / np);
      EXPECT_NEAR(projected, wo.z(), 1e-4) << alpha << " " << theta;
    }
  }
}

TEST(Analytic, HeightCorrelatedMaskingIsBoundedBySeparableOnes) {
  for (double alpha : {0.05, 0.4, 1.0})
    for (double ci : {0.05, 0.5, 1.0})
      for (double co : {0.1, 0.7, 1.0}) {
        const double g2 = microfacet::smith_g2_height_correlated(ci, co, alpha);
        const double g1i = microfacet::smith_g1(ci, alpha), g1o = microfacet::smith_g1(co, alpha);
        EXPECT_LE(g2, std::min(g1i, g1o) + 1e-15);
        EXPECT_GE(g2, g1i * g1o - 1e-15);  // correlation can only reduce the loss
      }
  EXPECT_DOUBLE_EQ(microfacet::smith_g2_height_correlated(1.0, 1.0, 0.5), 1.0);
}

TEST(Analytic, DielectricFresnelMatchesKnownValues) {
  EXPECT_NEAR(microfacet::fresnel_dielectric(1.0, 1.5), 0.04, 1e-12);
  EXPECT_NEAR(microfacet::fresnel_dielectric(0.0, 1.5), 1.0, 1e-12);
  // At Brewster's angle p-polarised reflectance vanishes and Rs = cos^2(2 theta_B).
  const double brewster = std::atan(1.5);
  const double rs = std::pow(std::cos(2 * brewster), 2);
  EXPECT_NEAR(microfacet::fresnel_dielectric(std::cos(brewster), 1.5), 0.5 * rs, 1e-12);
  EXPECT_NEAR(microfacet::dielectric_f0(1.5), 0.04, 1e-15);
  // Index 1: no interface, no reflection.
  EXPECT_NEAR(microfacet::fresnel_dielectric(0.3, 1.0), 0.0, 1e-15);
}

TEST(Analytic, SchlickFresnelGoesFromF0ToOne) {
  const Rgb f0(0.95, 0.64, 0.54);
  EXPECT_TRUE((microfacet::fresnel_schlick(f0, 1.0) - f0).abs().maxCoeff() < 1e-15);
  EXPECT_TRUE((microfacet::fresnel_schlick(f0, 0.0) - 1.0).abs().maxCoeff() < 1e-15);
  const Rgb mid = microfacet::fresnel_schlick(f0, 0.5);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mid[c], f0[c] + (1 - f0[c]) / 32.0, 1e-15);
}

TEST(Analytic, BlinnPhongNormalisationMatchesClosedFormLimits) {
  EXPECT_NEAR(BlinnPhong::normalisation(0.0), 1.0 / kPi, 1e-15);
  // For large n, c(n) -> (n + 6) / (8 pi) + O(1/n): the familiar (n + 8) / (8 pi) approximation.
  const double n = 1e4;
  EXPECT_NEAR(BlinnPhong::normalisation(n) / ((n + 8) / (8 * kPi)), 1.0, 1e-3);
}

TEST(Analytic, ValidateRejectsParametersOutsideTheirRanges) {
  EXPECT_THROW(validate(GgxConductor{Rgb(1.2, 0.5, 0.5), 0.1}), Error);
  EXPECT_THROW(validate(GgxConductor{Rgb::Constant(0.5), 0.0}), Error);
  EXPECT_THROW(validate(RoughPlastic{Rgb::Constant(0.5), 0.1, 3.0, 1.0}), Error);
  EXPECT_THROW(validate(BlinnPhong{Rgb::Constant(0.5), 10.0, Rgb::Constant(0.6)}), Error);
  EXPECT_THROW(validate(Lambertian{Rgb(0.5, -0.1, 0.5)}), Error);
  EXPECT_NO_THROW(validate(RoughPlastic{}));
  EXPECT_NO_THROW(validate(BlinnPhong{Rgb::Constant(0.1), 50.0, Rgb::Constant(0.9)}));
}

}  // namespace
}  // namespace matlas
