#include <gtest/gtest.h>

#include "brdf/albedo.h"

namespace matlas {
namespace {

TEST(Albedo, LambertianTableHasItsAlbedo) {
  const Rgb rho(0.8, 0.5, 0.2);
  BrdfTable table(MerlDims{});
  for (std::size_t b = 0; b < table.bins(); ++b)
    for (int c = 0; c < 3; ++c) table.set_value(c, b, rho[c] / kPi);
  for (double theta : {0.0, 0.5, 1.2}) {
    const Rgb a = directional_albedo(table, theta);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], rho[c], 1e-3) << "theta " << theta;
  }
}

TEST(Albedo, QuadratureIntegratesCosineExactly) {
  // pi * mean of f over cosine-distributed directions: for f = 1/pi the integral is 1, and for
  // f = cos(theta_i)/pi it is 2/3 (the midpoint rule is exact for a linear integrand in u).
  const auto one = directional_albedo([](const Vec3&, const Vec3&) { return Rgb(1 / kPi, 1 / kPi, 1 / kPi); },
                                      Vec3::UnitZ(), 64);
  EXPECT_NEAR(one[0], 1.0, 1e-12);
  const auto cos = directional_albedo(
      [](const Vec3& wi, const Vec3&) { return Rgb::Constant(wi.z() * wi.z() / kPi); }, Vec3::UnitZ(), 64);
  EXPECT_NEAR(cos[0], 0.5, 1e-12);
}

}  // namespace
}  // namespace matlas
