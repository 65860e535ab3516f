// Environment maps: lookups, importance sampling consistent with its density, files, assets.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/check.h"
#include "core/error.h"
#include "render/assets.h"
#include "render/environment.h"
#include "render/sampling.h"
#include "render_test_util.h"
#include "support/temp_dir.h"

namespace matlas::render {
namespace {

/// Integral of the map over the sphere: sum of texel radiance times texel solid angle.
Rgb map_integral(const Image& map) {
  Rgb sum = Rgb::Zero();
  for (int y = 0; y < map.height; ++y) {
    const double t0 = kPi * y / map.height, t1 = kPi * (y + 1) / map.height;
    const double solid = (std::cos(t0) - std::cos(t1)) * 2.0 * kPi / map.width;
    for (int x = 0; x < map.width; ++x) {
      const float* p = map.pixel(x, y);
      sum += Rgb(p[0], p[1], p[2]) * solid;
    }
  }
  return sum;
}

TEST(Environment, ImportanceSamplingEstimatesTheMapIntegral) {
  const Image map = test::synthetic_environment();
  const Environment env(map, 25.0);
  const Rgb expected = map_integral(map);
  Rgb estimate = Rgb::Zero();
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    SampleStream s(3, static_cast<std::uint64_t>(i), 0);
    double pdf;
    const Vec3 d = env.sample(s.next(), s.next(), &pdf);
    ASSERT_NEAR(d.norm(), 1.0, 1e-12);
    ASSERT_GT(pdf, 0.0);
    ASSERT_NEAR(env.pdf(d), pdf, 1e-6 * pdf);
    estimate += env.eval(d) / pdf;
  }
  estimate /= n;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(estimate[c], expected[c], 0.01 * expected[c]);
}

TEST(Environment, DensityIntegratesToOne) {
  const Environment env(test::synthetic_environment());
  // Midpoint rule over (theta, phi).
  double total = 0;
  const int nt = 400, np = 800;
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const double t = kPi * (i + 0.5) / nt, p = 2 * kPi * (j + 0.5) / np;
      const Vec3 d(std::sin(t) * std::cos(p), std::cos(t), std::sin(t) * std::sin(p));
      total += env.pdf(d) * std::sin(t) * (kPi / nt) * (2 * kPi / np);
    }
  EXPECT_NEAR(total, 1.0, 2e-3);
}

TEST(Environment, UpIsTheTopRowAndConstantIsUniform) {
  Image map(8, 4);
  for (int x = 0; x < 8; ++x) map.pixel(x, 0)[0] = 5.0f;
  const Environment env(map);
  EXPECT_EQ(env.eval(Vec3(0, 1, 0))[0], 5.0);
  EXPECT_EQ(env.eval(Vec3(0, -1, 0))[0], 0.0);
  const Environment c = Environment::constant(Rgb(1, 2, 3));
  EXPECT_EQ(c.eval(Vec3(0.6, 0, 0.8))[1], 2.0);
  EXPECT_NEAR(c.pdf(Vec3(1, 0, 0)), 1.0 / (4 * kPi), 1e-15);
}

TEST(Environment, LoadsExrFilesAndNamesMissingOnes) {
  test::TempDir dir;
  const Image map = test::synthetic_environment();
  write_exr(dir / "sky.exr", map);
  const Environment env = Environment::load(dir / "sky.exr");
  EXPECT_EQ(env.width(), 32);
  EXPECT_EQ(env.height(), 16);
  EXPECT_FLOAT_EQ(static_cast<float>(env.eval(Vec3(0, 1, 0))[2]), map.pixel(0, 0)[2]);
  try {
    resolve_environment((dir / "nope.exr").string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.exr"), std::string::npos);
  }
}

TEST(Environment, InstalledAssetsDecode) {
  const auto names = installed_environments();
  if (names.empty()) GTEST_SKIP() << "assets not installed (scripts/install-assets.sh)";
  const Environment env = Environment::load(resolve_environment(names.front()));
  EXPECT_EQ(env.width(), 512);
  EXPECT_EQ(env.height(), 256);
  EXPECT_GT(env.eval(Vec3(0, 1, 0)).sum(), 0.0);
}

TEST(Environment, ADistributionOfTheWrongShapeIsACallersBug) {
  // The environment builds its weights from the map it holds: weights that do not fill the
  // cols x rows table are a bug in matlas, refused by name rather than read past their end.
  const std::vector<double> weights(5, 1.0);
  try {
    const Distribution2D d(weights, 2, 3);
    ADD_FAILURE() << "a 2 x 3 distribution of 5 weights was accepted";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("weights.size() == "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(5 vs 6)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Distribution2D(std::vector<double>{}, 0, 0), InternalError);
  EXPECT_NO_THROW(Distribution2D(std::vector<double>(6, 1.0), 2, 3));
}

}  // namespace
}  // namespace matlas::render
