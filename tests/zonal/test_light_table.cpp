// The direct lights' table (zonal/light_table.h): phi_d averaged in groups, the thetas kept, read
// trilinearly as the shader's 3D texture; exact for a table constant in phi_d, linear in the
// table, missing bins filled from below in theta_h, and the reduced grid for any phi_d count.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "brdf/analytic.h"
#include "brdf/brdf_table.h"
#include "brdf/merl_grid.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "zonal/light_table.h"

namespace matlas::zonal {
namespace {

Vec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

TEST(LightTable, ReducedGridsKeepTheThetasAndAtMost15PhiBins) {
  EXPECT_EQ(LightTable::reduced_dims(MerlDims{}), (MerlDims{90, 90, 15}));
  EXPECT_EQ(LightTable::reduced_dims(MerlDims{16, 16, 32}), (MerlDims{16, 16, 8}));  // 32 = 4 x 8
  EXPECT_EQ(LightTable::reduced_dims(MerlDims{8, 8, 16}), (MerlDims{8, 8, 8}));
  EXPECT_EQ(LightTable::reduced_dims(MerlDims{8, 8, 7}), (MerlDims{8, 8, 7}));
  EXPECT_EQ(LightTable::reduced_dims(MerlDims{90, 90, 90}), (MerlDims{90, 90, 15}));
}

TEST(LightTable, ATableConstantInPhiIsReadAsItsOwnSmoothLookup) {
  // Values of (theta_h, theta_d) only: averaging over phi_d changes nothing, and the trilinear
  // read equals the full table's (BrdfTable::lookup_smooth) everywhere.
  const MerlDims dims{30, 30, 60};
  BrdfTable table(dims);
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k)
        for (int c = 0; c < 3; ++c)
          table.set_value(c, dims.flat(i, j, k), (c + 1) * std::exp(-0.2 * i) + 0.01 * j * j + 0.1);
  const LightTable reduced = LightTable::reduce(table);
  EXPECT_EQ(reduced.dims(), (MerlDims{30, 30, 15}));
  double worst = 0;
  for (double ti : {0.0, 0.2, 0.7, 1.2, 1.5})
    for (double to : {0.05, 0.4, 0.9, 1.4})
      for (double phi : {0.0, 0.8, 2.0, 3.1, 4.5}) {
        const Vec3 wi = direction(ti, phi), wo = direction(to, 0.3);
        const Rgb a = reduced.eval(wi, wo), b = table.lookup_smooth(wi, wo);
        worst = std::max(worst, ((a - b).abs() / b.abs().max(1e-12)).maxCoeff());
      }
  EXPECT_LT(worst, 1e-6);
}

TEST(LightTable, IsLinearInTheTable) {
  const MerlDims dims{16, 16, 32};
  const BrdfTable a = tabulate(GgxConductor{Rgb(0.9, 0.6, 0.3), 0.15}, dims);
  const BrdfTable b = tabulate(Lambertian{Rgb(0.2, 0.5, 0.7)}, dims);
  BrdfTable mix(dims);
  for (std::size_t bin = 0; bin < dims.bins(); ++bin)
    for (int c = 0; c < 3; ++c) {
      if (!a.measured(c, bin) || !b.measured(c, bin)) {
        mix.set_missing(c, bin);
        continue;
      }
      mix.set_value(c, bin, 0.7 * a.value(c, bin) + 0.2 * b.value(c, bin));  // (negative values read as missing)
    }
  const LightTable la = LightTable::reduce(a), lb = LightTable::reduce(b), lm = LightTable::reduce(mix);
  double largest = 0, worst = 0;
  for (std::size_t v = 0; v < lm.values().size(); ++v) {
    const double combined = 0.7 * la.values()[v] + 0.2 * lb.values()[v];
    largest = std::max(largest, static_cast<double>(std::abs(lm.values()[v])));
    worst = std::max(worst, std::abs(combined - lm.values()[v]));
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-5 * largest);
}

TEST(LightTable, MissingBinsTakeTheNearestMeasuredValueBelowInThetaH) {
  const MerlDims dims{8, 8, 15};
  BrdfTable table(dims);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 15; ++k)
        for (int c = 0; c < 3; ++c) {
          if (i + j >= 10) table.set_missing(c, dims.flat(i, j, k));  // the unmeasured corner
          else table.set_value(c, dims.flat(i, j, k), 1.0 + i + 10.0 * j);
        }
  const LightTable reduced = LightTable::reduce(table);
  for (int j = 3; j < 8; ++j) {
    const int last = 9 - j;  // the last measured theta_h bin of this theta_d
    for (int i = last + 1; i < 8; ++i)
      EXPECT_EQ(reduced.values()[reduced.dims().flat(i, j, 4) * 3], static_cast<float>(1.0 + last + 10.0 * j));
  }
  // A column with nothing measured reads 0.
  BrdfTable empty(dims);
  for (std::size_t bin = 0; bin < dims.bins(); ++bin)
    for (int c = 0; c < 3; ++c) empty.set_missing(c, bin);
  const LightTable none = LightTable::reduce(empty);
  for (float v : none.values()) EXPECT_EQ(v, 0.0f);
}

}  // namespace
}  // namespace matlas::zonal
