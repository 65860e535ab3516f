// Real spherical harmonics, zonal harmonics and the rotated-ZH basis of a band.
#include <gtest/gtest.h>

#include <cmath>

#include "brdf/types.h"
#include "zonal/basis.h"
#include "zonal/sh.h"

namespace matlas::zonal {
namespace {

// Gauss-free check: midpoint rule on a fine (theta, phi) grid is accurate to ~1e-6 for degree <= 8.
TEST(SphericalHarmonics, RealHarmonicsAreOrthonormal) {
  const int L = 6, nt = 400, np = 800;
  const std::size_t n = static_cast<std::size_t>((L + 1) * (L + 1));
  std::vector<double> gram(n * n, 0.0), y(n), p;
  for (int i = 0; i < nt; ++i) {
    const double t = kPi * (i + 0.5) / nt, w = std::sin(t) * (kPi / nt) * (2 * kPi / np);
    normalized_legendre(L, std::cos(t), p);
    for (int j = 0; j < np; ++j) {
      const double ph = 2 * kPi * (j + 0.5) / np;
      std::size_t q = 0;
      for (int l = 0; l <= L; ++l)
        for (int m = -l; m <= l; ++m) {
          const double pl = p[lm_index(l, std::abs(m))];
          y[q++] = m == 0 ? pl : std::sqrt(2.0) * pl * (m > 0 ? std::cos(m * ph) : std::sin(-m * ph));
        }
      for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = 0; b < n; ++b) gram[a * n + b] += w * y[a] * y[b];
    }
  }
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) EXPECT_NEAR(gram[a * n + b], a == b ? 1.0 : 0.0, 1e-4) << a << " " << b;
}

TEST(SphericalHarmonics, ZonalHarmonicsAreTheM0LegendreFunctions) {
  std::vector<double> z, p;
  for (double t : {-0.9, -0.3, 0.0, 0.42, 0.97}) {
    zonal_harmonics(40, t, z);
    normalized_legendre(40, t, p);
    for (int l = 0; l <= 40; ++l) EXPECT_NEAR(z[static_cast<std::size_t>(l)], p[lm_index(l, 0)], 1e-10) << l;
    // Closed forms: Y_2^0 = sqrt(5/4pi) (3t^2 - 1)/2, Y_3^0 = sqrt(7/4pi) (5t^3 - 3t)/2.
    EXPECT_NEAR(z[2], std::sqrt(5 / (4 * kPi)) * (3 * t * t - 1) / 2, 1e-14);
    EXPECT_NEAR(z[3], std::sqrt(7 / (4 * kPi)) * (5 * t * t * t - 3 * t) / 2, 1e-14);
  }
}

TEST(ZonalBasis, IsWellConditionedAndRecoversKernelCoefficients) {
  const ZonalBasis basis(32);
  EXPECT_EQ(basis.size(), 33u * 34u / 2u);
  for (int l = 1; l <= 32; ++l) EXPECT_LT(basis.condition(l), 2.5) << l;
  // A sum of band-l kernels with known lambdas, projected onto the even SH of band l on a
  // midpoint grid, then changed back with A_l^-1, returns the lambdas.
  const int l = 7, nt = 300, np = 600;
  std::vector<double> lambda(static_cast<std::size_t>(l) + 1);
  for (int k = 0; k <= l; ++k) lambda[static_cast<std::size_t>(k)] = std::sin(1.0 + 2.3 * k);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(l + 1);
  std::vector<double> p, z;
  for (int i = 0; i < nt; ++i) {
    const double t = kPi * (i + 0.5) / nt, w = std::sin(t) * (kPi / nt) * (2 * kPi / np);
    normalized_legendre(l, std::cos(t), p);
    for (int j = 0; j < np; ++j) {
      const double ph = 2 * kPi * (j + 0.5) / np;
      const Vec3 om(std::sin(t) * std::cos(ph), std::sin(t) * std::sin(ph), std::cos(t));
      double f = 0;
      for (int k = 0; k <= l; ++k) {
        zonal_harmonics(l, basis.direction(lm_index(l, k)).dot(om), z);
        f += lambda[static_cast<std::size_t>(k)] * z[static_cast<std::size_t>(l)];
      }
      for (int m = 0; m <= l; ++m)
        a(m) += w * f * (m ? std::sqrt(2.0) : 1.0) * p[lm_index(l, m)] * std::cos(m * ph);
    }
  }
  const Eigen::VectorXd back = basis.inverse(l) * a;
  for (int k = 0; k <= l; ++k) EXPECT_NEAR(back(k), lambda[static_cast<std::size_t>(k)], 1e-4) << k;
}

}  // namespace
}  // namespace matlas::zonal
