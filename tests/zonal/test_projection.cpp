// Projection of tables to rotated-ZH coefficients: Lambertian exactness, convergence in L,
// linearity in the table.
#include <gtest/gtest.h>

#include <cmath>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/check.h"
#include "core/error.h"
#include "zonal/projection.h"
#include "zonal/sh.h"

namespace matlas::zonal {
namespace {

struct Projected {
  ZonalProjector projector;
  ZonalCoefficients coefficients;
};

Projected project_lambertian(const Rgb& albedo, int bands, int theta_o_count) {
  ProjectionSettings s;
  s.bands = bands;
  s.theta_o_count = theta_o_count;
  ZonalProjector projector(s);
  ZonalCoefficients c = projector.project(tabulate(Lambertian{albedo}));
  return {std::move(projector), std::move(c)};
}

TEST(Projection, LambertianIsTheClampedCosineAroundTheNormal) {
  // (a/pi) max(cos, 0) = (a/pi) sum_l c_l Y_l^0(n . w), with c_0 = sqrt(pi)/2, c_1 = sqrt(pi/3),
  // c_2 = sqrt(5 pi)/8, c_l = 0 for odd l >= 3: only the kernels around the normal (k = 0).
  const Rgb albedo(0.8, 0.5, 0.2);
  const ZonalCoefficients c = project_lambertian(albedo, 6, 8).coefficients;
  const double expected[] = {std::sqrt(kPi) / 2, std::sqrt(kPi / 3), std::sqrt(5 * kPi) / 8, 0.0};
  for (int t = 0; t < 8; ++t)
    for (int l = 0; l <= 6; ++l)
      for (int k = 0; k <= l; ++k)
        for (int ch = 0; ch < 3; ++ch) {
          const double value = c.at(t, lm_index(l, k))[ch] / (albedo[ch] / kPi);
          if (k == 0 && l <= 3) {
            EXPECT_NEAR(value, expected[l], 2e-4) << t << " " << l;
          } else if (k > 0) {
            EXPECT_NEAR(value, 0.0, 2e-4) << t << " " << l << " " << k;
          }
        }
}

TEST(Projection, LambertianAtL2ReconstructsItsTruncatedExpansion) {
  const Projected p = project_lambertian(Rgb::Constant(0.6), 2, 4);
  const ZonalProjector& projector = p.projector;
  const ZonalCoefficients& c = p.coefficients;
  for (double ti : {0.0, 0.4, 1.2, 2.0}) {
    const Vec3 wi(std::sin(ti), 0.0, std::cos(ti));
    const double t = std::cos(ti);
    const double expected = 0.6 / kPi *
                            (std::sqrt(kPi) / 2 / std::sqrt(4 * kPi) + std::sqrt(kPi / 3) * std::sqrt(3 / (4 * kPi)) * t +
                             std::sqrt(5 * kPi) / 8 * std::sqrt(5 / (4 * kPi)) * (3 * t * t - 1) / 2);
    EXPECT_NEAR(reconstruct(projector.basis(), c, 0.7, wi)[0], expected, 1e-4);
  }
}

/// Root-mean-square error of the reconstructed slices against the table's over the upper
/// hemisphere, relative to the slices' RMS, at a few view angles.
double slice_error(const BrdfTable& table, int L) {
  ProjectionSettings s;
  s.bands = L;
  s.theta_o_count = 16;
  const ZonalProjector projector(s);
  const ZonalCoefficients c = projector.project(table);
  double err = 0, ref = 0;
  for (double to : {0.2, 0.7, 1.1}) {
    const Vec3 wo(std::sin(to), 0, std::cos(to));
    for (int i = 0; i < 24; ++i)
      for (int j = 0; j < 48; ++j) {
        const double ti = (i + 0.5) / 24 * kPi / 2, ph = (j + 0.5) / 48 * 2 * kPi;
        const Vec3 wi(std::sin(ti) * std::cos(ph), std::sin(ti) * std::sin(ph), std::cos(ti));
        const double truth = table.lookup(wi, wo)[1] * wi.z(), w = std::sin(ti);
        const double d = reconstruct(projector.basis(), c, to, wi)[1] - truth;
        err += w * d * d;
        ref += w * truth * truth;
      }
  }
  return std::sqrt(err / ref);
}

TEST(Projection, SliceErrorDecreasesWithBands) {
  RoughPlastic plastic;
  plastic.alpha = 0.25;
  plastic.diffuse = Rgb(0.3, 0.4, 0.5);
  const BrdfTable table = tabulate(plastic);
  double previous = 1e9;
  for (int L : {2, 4, 8, 16}) {
    const double e = slice_error(table, L);
    EXPECT_LT(e, previous * 0.85) << "L = " << L;
    previous = e;
  }
  EXPECT_LT(previous, 0.05);
}

TEST(Projection, CoefficientsAreLinearInTheTable) {
  RoughPlastic plastic;
  plastic.alpha = 0.08;
  const BrdfTable a = tabulate(plastic), b = tabulate(GgxConductor{Rgb(0.9, 0.6, 0.3), 0.2});
  BrdfTable mix(a.dims());
  for (std::size_t v = 0; v < mix.size(); ++v) mix.stored()[v] = 0.3 * a.stored()[v] + 0.7 * b.stored()[v];
  ProjectionSettings s;
  s.bands = 10;
  s.theta_o_count = 6;
  const ZonalProjector projector(s);
  const ZonalCoefficients ca = projector.project(a), cb = projector.project(b), cm = projector.project(mix);
  const ZonalCoefficients combined = combine({&ca, &cb}, {0.3, 0.7});
  double scale = 0;
  for (double v : cm.values) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0.1);
  for (std::size_t i = 0; i < cm.values.size(); ++i) EXPECT_NEAR(combined.values[i], cm.values[i], 1e-12 * scale);
  EXPECT_THROW(combine({&ca, &cb}, {1.0}), InternalError);  // a caller's bug, not bad input
}

TEST(Projection, RejectsBadSettingsAndTables) {
  ProjectionSettings s;
  s.bands = -1;
  EXPECT_THROW(ZonalProjector{s}, Error);
  s.bands = 4;
  s.theta_o_count = 0;
  EXPECT_THROW(ZonalProjector{s}, Error);
  s.theta_o_count = 4;
  const ZonalProjector projector(s);
  EXPECT_THROW(projector.project(BrdfTable(MerlDims{9, 9, 18})), Error);
}

}  // namespace
}  // namespace matlas::zonal
