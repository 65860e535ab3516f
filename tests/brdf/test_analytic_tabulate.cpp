// Tabulating analytic BRDFs onto the MERL grid.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "brdf/albedo.h"
#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"

namespace matlas {
namespace {

TEST(Tabulate, LambertianTableHoldsAlbedoOverPiAboveTheHorizonAndZeroBelow) {
  const Lambertian f{Rgb(0.8, 0.5, 0.2)};
  const MerlDims dims;
  const BrdfTable table = tabulate(f, dims);
  ASSERT_EQ(table.dims(), dims);
  EXPECT_EQ(table.missing_count(), 0u);
  std::size_t above = 0, below = 0;
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; k += 7) {
        const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
        const bool up = d.wi.z() > 0 && d.wo.z() > 0;
        (up ? above : below)++;
        for (int c = 0; c < 3; ++c) {
          const double v = table.value(c, dims.flat(i, j, k));
          ASSERT_NEAR(v, up ? f.albedo[c] / kPi : 0.0, 1e-15) << i << " " << j << " " << k;
        }
      }
  EXPECT_GT(above, 0u);
  EXPECT_GT(below, 0u);  // the grid does reach below the horizon (theta_h + theta_d > 90 deg)
}

TEST(Tabulate, LambertianTableHasItsAlbedo) {
  const Rgb rho(0.8, 0.5, 0.2);
  const BrdfTable table = tabulate(Lambertian{rho});
  for (double theta : {0.0, 0.5, 1.0, 1.2}) {
    const Rgb a = directional_albedo(table, theta);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], rho[c], 1e-3) << "theta " << theta;
  }
}

TEST(Tabulate, EveryBinIsTheFunctionAtItsCentre) {
  const RoughPlastic f{Rgb(0.2, 0.4, 0.9), 0.3, 1.5, 1.0};
  const MerlDims dims{30, 30, 60};
  const BrdfTable table = tabulate(f, dims);
  std::mt19937 rng(3);
  for (int n = 0; n < 500; ++n) {
    const int i = static_cast<int>(rng() % 30), j = static_cast<int>(rng() % 30), k = static_cast<int>(rng() % 60);
    const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
    const Rgb expected = f(d.wi, d.wo);
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(table.value(c, dims.flat(i, j, k)), expected[c], 1e-12 * std::max(1.0, expected[c]));
  }
  // A lookup with the bin's own centre directions finds that bin.
  const DirectionPair d = from_half_diff(bin_centre(dims, 4, 10, 20));
  EXPECT_NEAR(table.lookup(d.wi, d.wo)[1], f(d.wi, d.wo)[1], 1e-12);
}

TEST(Tabulate, TablesOfEveryModelAreFiniteAndNonNegative) {
  const MerlDims dims{45, 45, 90};
  const AnalyticBrdf models[] = {
      GgxConductor{Rgb(1.0, 0.78, 0.34), 0.001},  // the sharpest lobe accepted
      RoughPlastic{Rgb::Ones(), 1.0, 2.0, 1.0},
      BlinnPhong{Rgb::Constant(1.0), 1e5, Rgb::Zero()},
  };
  for (const AnalyticBrdf& m : models) {
    const BrdfTable table = tabulate([&](const Vec3& i, const Vec3& o) { return evaluate(m, i, o); }, dims);
    for (double v : table.stored()) {
      ASSERT_TRUE(std::isfinite(v)) << describe(m);
      ASSERT_GE(v, 0.0) << describe(m);
    }
  }
}

TEST(Tabulate, NonFiniteOrNegativeValuesAreRefused) {
  const MerlDims dims{8, 8, 16};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(tabulate([&](const Vec3&, const Vec3&) { return Rgb(0.1, nan, 0.1); }, dims), Error);
  EXPECT_THROW(tabulate([](const Vec3& wi, const Vec3&) { return Rgb::Constant(wi.x() > 0.5 ? -1.0 : 0.1); }, dims),
               Error);
  EXPECT_THROW(tabulate([](const Vec3&, const Vec3&) { return Rgb::Constant(HUGE_VAL); }, dims), Error);
}

TEST(Tabulate, TabulatedAlbedoStaysBelowOne) {
  // Nearest-bin lookups of the table, for white worst cases at roughnesses the grid resolves.
  const AnalyticBrdf models[] = {
      GgxConductor{Rgb::Ones(), 0.3},
      RoughPlastic{Rgb::Ones(), 0.3, 1.5, 1.0},
      BlinnPhong{Rgb::Constant(0.3), 20.0, Rgb::Constant(0.7)},
  };
  for (const AnalyticBrdf& m : models) {
    const BrdfTable table = tabulate([&](const Vec3& i, const Vec3& o) { return evaluate(m, i, o); });
    for (double theta : {0.0, 0.6, 1.0, 1.3, 1.5}) {
      const Rgb a = directional_albedo(table, theta);
      EXPECT_LE(a.maxCoeff(), 1.0 + 5e-3) << describe(m) << " theta " << theta;
      // and close to the functor's own albedo
      const Rgb b = directional_albedo([&](const Vec3& i, const Vec3& o) { return evaluate(m, i, o); },
                                       direction_at_theta(theta), 192);
      EXPECT_NEAR(a.maxCoeff(), b.maxCoeff(), 0.02) << describe(m) << " theta " << theta;
    }
  }
}

}  // namespace
}  // namespace matlas
