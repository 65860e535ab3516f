#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "brdf/albedo.h"
#include "brdf/albedo_operator.h"
#include "brdf/analytic.h"
#include "brdf/analytic_albedo.h"
#include "brdf/tabulate.h"

namespace matlas {
namespace {

constexpr double kDeg = kPi / 180.0;

/// A table that is `value` where keep(i, j, k) holds and 0 elsewhere (every bin measured).
template <class Keep>
BrdfTable indicator_table(const MerlDims& dims, const Rgb& value, const Keep& keep) {
  BrdfTable table(dims);
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k)
        if (keep(i, j, k))
          for (int c = 0; c < 3; ++c) table.set_value(c, dims.flat(i, j, k), value[c]);
  return table;
}

TEST(Albedo, LambertianTableHasItsAlbedo) {
  const Rgb rho(0.8, 0.5, 0.2);
  const BrdfTable table = indicator_table(MerlDims{}, rho / kPi, [](int, int, int) { return true; });
  // Measured: within 5e-5 at every angle, grazing included (the horizon's kink in the
  // integrand is what is left).
  for (double deg : {0.0, 0.5, 30.0, 60.0, 80.5, 85.5, 89.5}) {
    const Rgb a = directional_albedo(table, deg * kDeg);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], rho[c], 1e-4 * rho[c]) << deg << " degrees";
  }
}

/// A narrow mirror-like lobe: f = v wherever theta_h < theta_m (the first m theta_h bins),
/// 0 elsewhere. In half-vector space (dwi = 4 (wo.h) dwh, cos theta_i = 2 (wo.h) h_z - wo_z),
/// integrating over the cap theta_h < theta_m in closed form:
///   a(theta_o) = 4 pi v sin^2(theta_m) [cos^2(theta_o) cos^2(theta_m) + sin^2(theta_o) sin^2(theta_m) / 2].
double cap_albedo(double v, double theta_m, double theta_o) {
  const double sm = std::sin(theta_m), cm = std::cos(theta_m), so = std::sin(theta_o), co = std::cos(theta_o);
  return 4.0 * kPi * v * sm * sm * (co * co * cm * cm + so * so * sm * sm / 2.0);
}

TEST(Albedo, MirrorLikeLobeHasItsClosedFormAlbedo) {
  const MerlDims dims{};
  for (int m : {1, 2, 5}) {
    // theta_h < theta_m covers bins 0 .. m-1 exactly (theta_h = u^2 pi/2, bin i = [i, i+1)/90 in u).
    const double theta_m = std::pow(m / 90.0, 2) * kPi / 2.0;
    // Normalised so that the albedo at normal incidence is 0.9: a mirror with Fresnel 0.9.
    const double v = 0.9 / cap_albedo(1.0, theta_m, 0.0);
    const BrdfTable table = indicator_table(dims, Rgb::Constant(v), [m](int i, int, int) { return i < m; });
    // Two Gauss points per bin in u leave a relative error of about (1/90)^4 (the integrand's
    // u^7 term); at 89.5 degrees cos(theta_i) varies across the cap by a sizeable part of itself.
    for (double deg : {0.0, 0.5, 30.5, 60.5, 80.5, 89.5}) {
      const double expected = cap_albedo(v, theta_m, deg * kDeg);
      const Rgb a = directional_albedo(table, deg * kDeg);
      EXPECT_NEAR(a[1], expected, (deg < 85 ? 1e-6 : 1e-4) * expected) << "m " << m << ", " << deg << " degrees";
    }
  }
  // The first bin is 0.011 degrees wide: a regular cosine grid of directions never lands in it
  // (the integral this rule replaces).
  const double theta_1 = std::pow(1 / 90.0, 2) * kPi / 2.0;
  const BrdfTable mirror =
      indicator_table(dims, Rgb::Constant(1.0 / cap_albedo(1.0, theta_1, 0.0)), [](int i, int, int) { return i == 0; });
  EXPECT_EQ(directional_albedo([&](const Vec3& wi, const Vec3& wo) { return mirror.lookup(wi, wo); }, Vec3::UnitZ(),
                               256)[0],
            0.0);
  EXPECT_NEAR(directional_albedo(mirror, 0.0)[0], 1.0, 1e-7);
}

TEST(Albedo, ThetaDBinsAreLookedUpAsMerlDoes) {
  // f = 1/pi in the theta_d bins below 45 degrees, i.e. where wi . wo > 0 (theta_d is half the
  // angle between wi and wo), 0 elsewhere. The projected solid
  // angle of {wi . wo < 0} within the hemisphere is (pi/2)(1 - cos theta_o) (a half disc minus a
  // half ellipse), so a(theta_o) = (1 + cos theta_o) / 2.
  const MerlDims dims{};
  const BrdfTable table = indicator_table(dims, Rgb::Constant(1 / kPi), [](int, int j, int) { return j < 45; });
  // The jump at theta_d = 45 degrees cuts across the quadrature points: an error of a few 1e-3
  // (4.2e-3 at 60 degrees, where the jump lines up worst with the azimuths).
  for (double deg : {0.0, 20.5, 45.5, 60.0, 70.5, 85.5}) {
    const double expected = 0.5 * (1.0 + std::cos(deg * kDeg));
    EXPECT_NEAR(directional_albedo(table, deg * kDeg)[0], expected, 5e-3) << deg << " degrees";
  }
}

TEST(Albedo, NormalIncidenceSplitsTheDegeneratePhiD) {
  // At normal incidence wi, wo, h and the normal share a plane: phi_d is 0 or pi (the first or
  // the last phi_d bin) as rounding decides. The rule gives each half the weight, the limit of
  // theta_o -> 0: a table of 1/pi in either bin alone has albedo 1/2.
  const MerlDims dims{};
  const BrdfTable first = indicator_table(dims, Rgb::Constant(1 / kPi), [](int, int, int k) { return k == 0; });
  const BrdfTable last = indicator_table(dims, Rgb::Constant(1 / kPi), [&](int, int, int k) { return k == dims.phi_d - 1; });
  EXPECT_NEAR(directional_albedo(first, 0.0)[0], 0.5, 1e-4);
  EXPECT_NEAR(directional_albedo(last, 0.0)[0], 0.5, 1e-4);
}

TEST(Albedo, SharpTabulatedLobeMatchesItsFunction) {
  // A GGX mirror (F0 = 1, alpha = 0.02: a lobe about a degree wide) tabulated at bin centres
  // against the functor's own albedo by importance sampling: independent integrals of nearly
  // the same function (the table is piecewise constant per bin).
  const GgxConductor f{Rgb::Ones(), 0.02};
  const BrdfTable table = tabulate(f);
  for (double deg : {0.0, 30.5, 60.5}) {
    const double want = half_vector_albedo(f, direction_at_theta(deg * kDeg), GgxHalfSampler{f.alpha}, 512)[0];
    EXPECT_NEAR(directional_albedo(table, deg * kDeg)[0], want, 0.01 * want) << deg << " degrees";
  }
}

TEST(Albedo, RuleIsOneTermPerBinAndAgreesWithTheLookup) {
  const MerlDims dims{};
  const std::vector<AlbedoTerm> rule = albedo_rule(dims, 40.5 * kDeg);
  for (std::size_t k = 1; k < rule.size(); ++k) ASSERT_LT(rule[k - 1].bin, rule[k].bin);
  for (const AlbedoTerm& t : rule) ASSERT_GT(t.weight, 0.0);
  // A random table: the rule applied by hand equals directional_albedo, and a table that is 1
  // in one bin's theta_h slice picks the weights of exactly that slice.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  BrdfTable table(dims);
  for (std::size_t b = 0; b < table.bins(); ++b) table.set_value(0, b, u(rng));
  double by_hand = 0;
  for (const AlbedoTerm& t : rule) by_hand += t.weight * table.value(0, t.bin);
  EXPECT_NEAR(directional_albedo(table, 40.5 * kDeg)[0], by_hand, 1e-12 * by_hand);
  // Missing values count as 0.
  BrdfTable holes = table;
  double without = by_hand;
  for (std::size_t k = 0; k < rule.size(); k += 7) {
    holes.set_missing(0, rule[k].bin);
    without -= rule[k].weight * table.value(0, rule[k].bin);
  }
  EXPECT_NEAR(directional_albedo(holes, 40.5 * kDeg)[0], without, 1e-12 * without);
}

TEST(Albedo, OperatorColumnsAreTheRules) {
  const MerlDims dims{30, 30, 60};
  const AlbedoQuadrature q{2, 32};
  const auto op = albedo_operator(dims, 9, q);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  BrdfTable table(dims);
  Eigen::VectorXd red(static_cast<Eigen::Index>(dims.bins()));
  for (std::size_t b = 0; b < dims.bins(); ++b) {
    const double v = u(rng);
    table.set_value(0, b, v);
    red[static_cast<Eigen::Index>(b)] = v;
  }
  const Eigen::VectorXd curve = op.transpose() * red;
  const std::vector<Rgb> direct = albedo_curve(table, 9, q);
  for (int t = 0; t < 9; ++t) EXPECT_NEAR(curve[t], direct[static_cast<std::size_t>(t)][0], 1e-12) << t;
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
