// Energy of the analytic BRDFs: directional albedo <= 1 everywhere, the limits it must reach
// (GGX -> F0 as alpha -> 0, Blinn-Phong's normalisation), and white-furnace behaviour.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "brdf/albedo.h"
#include "brdf/analytic.h"
#include "brdf/analytic_albedo.h"

namespace matlas {
namespace {

const double kAnglesDeg[] = {0, 20, 40, 60, 75, 85, 89};
const double kAlphas[] = {0.02, 0.05, 0.1, 0.3, 0.6, 1.0};

Vec3 view(double degrees) { return direction_at_theta(degrees * kPi / 180.0); }

/// Albedo of a sharp GGX lobe by importance sampling (the cosine quadrature cannot see it).
template <class F>
Rgb ggx_albedo(const F& f, const Vec3& wo, double alpha, int res = 192) {
  return half_vector_albedo(f, wo, GgxHalfSampler{alpha}, res);
}

TEST(AnalyticEnergy, ImportanceSamplingAgreesWithCosineQuadratureOnBroadLobes) {
  // Two independent quadratures of the same integral (alpha 0.5 is smooth enough for both).
  const GgxConductor f{Rgb(1.0, 0.7, 0.3), 0.5};
  for (double deg : {0.0, 45.0, 75.0}) {
    const Rgb a = ggx_albedo(f, view(deg), f.alpha, 256);
    const Rgb b = directional_albedo(f, view(deg), 512);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 5e-3) << deg;
  }
}

TEST(AnalyticEnergy, GgxConductorAlbedoTendsToF0AsRoughnessVanishes) {
  // A near-delta lobe reflects F(theta_o) ~ F0 at normal incidence, minus a tiny masking loss.
  const Rgb f0(0.955, 0.638, 0.538);
  double previous_error = 1.0;
  for (double alpha : {0.1, 0.02, 0.005}) {
    const GgxConductor f{f0, alpha};
    const Rgb a = ggx_albedo(f, Vec3::UnitZ(), alpha, 256);
    const double error = ((a - f0).abs() / f0).maxCoeff();
    EXPECT_LE(error, previous_error) << alpha;
    previous_error = error;
    if (alpha <= 0.02) {
      EXPECT_LT(error, 0.01) << "alpha " << alpha << " albedo " << a.transpose();
    }
  }
}

TEST(AnalyticEnergy, WhiteFurnaceGgxWithUnitF0) {
  // F0 = 1 makes F = 1: the albedo is the single-scattering energy kept by Smith masking, close to
  // 1 for smooth surfaces and clearly below 1 for rough ones (the multiple-scattering loss).
  for (double deg : {0.0, 45.0, 70.0}) {
    const Rgb smooth = ggx_albedo(GgxConductor{Rgb::Ones(), 0.02}, view(deg), 0.02, 256);
    EXPECT_GT(smooth[0], 0.99) << deg;
    EXPECT_LE(smooth[0], 1.0 + 1e-3) << deg;
  }
  const double rough = ggx_albedo(GgxConductor{Rgb::Ones(), 1.0}, Vec3::UnitZ(), 1.0, 256)[0];
  // At alpha = 1, D = 1/pi: normals are cosine-distributed and half of them (theta_h > 45 deg)
  // reflect below the horizon at normal incidence, so less than half the energy is kept.
  EXPECT_LT(rough, 0.5);
  EXPECT_GT(rough, 0.25);
  // The loss grows with roughness.
  double previous = 1.0 + 1e-3;
  for (double alpha : kAlphas) {
    const double a = ggx_albedo(GgxConductor{Rgb::Ones(), alpha}, view(60), alpha)[0];
    EXPECT_LE(a, previous) << alpha;
    previous = a;
  }
}

TEST(AnalyticEnergy, GgxConductorAlbedoAtMostOne) {
  for (double alpha : kAlphas)
    for (double deg : kAnglesDeg) {
      const GgxConductor f{Rgb::Ones(), alpha};
      const double a = ggx_albedo(f, view(deg), alpha)[0];
      EXPECT_LE(a, 1.0 + 1e-3) << "alpha " << alpha << " theta " << deg;
      EXPECT_GT(a, 0.0);
    }
}

TEST(AnalyticEnergy, RoughPlasticAlbedoAtMostOne) {
  // Worst case: white base, full coating; IOR 1.5 (the catalogue's) and 2 (the largest accepted).
  for (double ior : {1.5, 2.0})
    for (double alpha : kAlphas)
      for (double deg : kAnglesDeg) {
        const RoughPlastic f{Rgb::Ones(), alpha, ior, 1.0};
        const Vec3 wo = view(deg);
        const double spec = ggx_albedo([&](const Vec3& i, const Vec3& o) { return f.specular_part(i, o); },
                                       wo, alpha)[0];
        const double diff =
            directional_albedo([&](const Vec3& i, const Vec3& o) { return f.diffuse_part(i, o); }, wo, 128)[0];
        EXPECT_LE(spec + diff, 1.0) << "ior " << ior << " alpha " << alpha << " theta " << deg;
        if (deg <= 60) {  // not absurdly dark (grazing views are dimmed by masking and (1 - F))
          EXPECT_GT(spec + diff, 0.7) << "ior " << ior << " alpha " << alpha << " theta " << deg;
        }
      }
}

TEST(AnalyticEnergy, BlinnPhongSpecularAlbedoIsExactlyKsAtNormalIncidenceAndLessElsewhere) {
  for (double n : {0.0, 1.0, 4.0, 30.0, 300.0, 3000.0, 30000.0}) {
    const BlinnPhong f{Rgb::Ones(), n, Rgb::Zero()};
    const PhongHalfSampler sampler{n};
    const double normal = half_vector_albedo(f, Vec3::UnitZ(), sampler, 256)[0];
    EXPECT_NEAR(normal, 1.0, 2e-3) << "n " << n;
    for (double deg : kAnglesDeg) {
      const double a = half_vector_albedo(f, view(deg), sampler, 128)[0];
      EXPECT_LE(a, 1.0 + 2e-3) << "n " << n << " theta " << deg;
    }
  }
}

TEST(AnalyticEnergy, BlinnPhongWithDiffuseAlbedoAtMostOne) {
  for (double n : {0.0, 5.0, 50.0, 500.0})
    for (double deg : kAnglesDeg) {
      const BlinnPhong f{Rgb::Constant(0.3), n, Rgb::Constant(0.7)};
      const Vec3 wo = view(deg);
      const double spec = half_vector_albedo([&](const Vec3& i, const Vec3& o) { return f.specular_part(i, o); },
                                             wo, PhongHalfSampler{n}, 128)[0];
      const double diff =
          directional_albedo([&](const Vec3& i, const Vec3& o) { return f.diffuse_part(i, o); }, wo, 64)[0];
      EXPECT_LE(spec + diff, 1.0 + 1e-3) << "n " << n << " theta " << deg;
    }
}

TEST(AnalyticEnergy, CosineQuadratureOnTheFunctorsDirectlyStaysBelowOne) {
  // The plain albedo integral of brdf/albedo.h, on the full models, where it resolves the lobes.
  const std::vector<AnalyticBrdf> models = {
      Lambertian{Rgb::Ones()},
      GgxConductor{Rgb::Ones(), 0.3},
      GgxConductor{Rgb::Ones(), 1.0},
      RoughPlastic{Rgb::Ones(), 0.3, 1.5, 1.0},
      RoughPlastic{Rgb::Ones(), 1.0, 2.0, 1.0},
      BlinnPhong{Rgb::Constant(0.2), 10.0, Rgb::Constant(0.8)},
  };
  for (const AnalyticBrdf& m : models)
    for (double deg : kAnglesDeg) {
      const Rgb a = directional_albedo([&](const Vec3& i, const Vec3& o) { return evaluate(m, i, o); },
                                       view(deg), 256);
      EXPECT_LE(a.maxCoeff(), 1.0 + 2e-3) << describe(m) << " theta " << deg;
    }
  const Rgb lambert = directional_albedo(Lambertian{Rgb(0.8, 0.5, 0.2)}, view(30), 64);
  EXPECT_NEAR(lambert[0], 0.8, 1e-12);
}

}  // namespace
}  // namespace matlas
