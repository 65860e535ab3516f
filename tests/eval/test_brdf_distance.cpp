// Metric properties of the evaluation's BRDF distances.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "eval/brdf_distance.h"

namespace matlas::eval {
namespace {

const MerlDims kSmall{6, 5, 8};

BrdfTable random_table(unsigned seed, double scale) {
  BrdfTable t(kSmall);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, scale);
  for (int c = 0; c < 3; ++c)
    for (std::size_t b = 0; b < t.bins(); ++b) t.set_value(c, b, u(rng));
  return t;
}

TEST(BrdfDistance, CosineFactorsAreCosinesAtBinCentres) {
  const std::vector<double> c = bin_cosine_factors(kSmall);
  ASSERT_EQ(c.size(), kSmall.bins());
  // theta_h = theta_d at the first bins is small: both directions near the normal.
  const DirectionPair d = from_half_diff(bin_centre(kSmall, 0, 0, 0));
  EXPECT_NEAR(c[0], d.wi.z() * d.wo.z(), 1e-15);
  for (double v : c) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

TEST(BrdfDistance, ZeroOnIdenticalTablesAndSymmetric) {
  const BrdfTable a = random_table(1, 2.0), b = random_table(2, 2.0);
  const BrdfDistance same = brdf_distance(a, a);
  EXPECT_EQ(same.cbrt_cosine, 0.0);
  EXPECT_EQ(same.cosine_rmse, 0.0);
  const BrdfDistance ab = brdf_distance(a, b), ba = brdf_distance(b, a);
  EXPECT_GT(ab.cbrt_cosine, 0.0);
  EXPECT_GT(ab.cosine_rmse, 0.0);
  EXPECT_DOUBLE_EQ(ab.cbrt_cosine, ba.cbrt_cosine);
  EXPECT_DOUBLE_EQ(ab.cosine_rmse, ba.cosine_rmse);
}

TEST(BrdfDistance, TriangleInequality) {
  const BrdfTable a = random_table(3, 1.0), b = random_table(4, 5.0), c = random_table(5, 0.1);
  EXPECT_LE(brdf_distance(a, c).cbrt_cosine,
            brdf_distance(a, b).cbrt_cosine + brdf_distance(b, c).cbrt_cosine + 1e-12);
  EXPECT_LE(brdf_distance(a, c).cosine_rmse,
            brdf_distance(a, b).cosine_rmse + brdf_distance(b, c).cosine_rmse + 1e-12);
}

TEST(BrdfDistance, MatchesDefinitionOnConstantTables) {
  // f = 1 and g = 8 everywhere: d_cbrt^2 = mean over values of (cbrt(c) - 2 cbrt(c))^2
  // = mean cbrt(c)^2; d_rmse^2 = 49 mean c^2, over values with c > 0.
  BrdfTable f(kSmall), g(kSmall);
  for (int ch = 0; ch < 3; ++ch)
    for (std::size_t b = 0; b < f.bins(); ++b) f.set_value(ch, b, 1.0), g.set_value(ch, b, 8.0);
  const std::vector<double> c = bin_cosine_factors(kSmall);
  double s1 = 0, s2 = 0;
  std::size_t count = 0;
  for (double v : c)
    if (v > 0) s1 += std::cbrt(v) * std::cbrt(v), s2 += 49 * v * v, ++count;
  const BrdfDistance d = brdf_distance(f, g);
  EXPECT_EQ(d.values, 3 * count);
  EXPECT_NEAR(d.cbrt_cosine, std::sqrt(s1 / static_cast<double>(count)), 1e-12);
  EXPECT_NEAR(d.cosine_rmse, std::sqrt(s2 / static_cast<double>(count)), 1e-12);
}

TEST(BrdfDistance, MissingValuesAreSkipped) {
  BrdfTable a = random_table(6, 1.0), b = a;
  const BrdfDistance full = brdf_distance(a, b);
  b.set_missing(1, 0);
  b.set_value(1, 1, 1000.0);  // a large difference that must count
  a.set_value(2, 0, 5.0);
  b.set_missing(2, 0);        // differs, but missing in b: must not count
  const BrdfDistance d = brdf_distance(a, b);
  EXPECT_LT(d.values, full.values);
  EXPECT_GT(d.cosine_rmse, 0.0);
  BrdfTable c = b;
  c.set_value(1, 1, a.value(1, 1));
  EXPECT_EQ(brdf_distance(a, c).cosine_rmse, 0.0);
}

TEST(BrdfDistance, RefusesDifferentDims) {
  EXPECT_THROW(brdf_distance(BrdfTable(kSmall), BrdfTable(MerlDims{4, 4, 4})), Error);
}

}  // namespace
}  // namespace matlas::eval
