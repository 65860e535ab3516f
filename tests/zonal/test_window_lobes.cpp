// Band windows (zonal/window.h) and sharp lobes (zonal/lobes.h): window factors, the ringing of
// a truncated delta, the lobes' Legendre coefficients and maps against closed forms, a lobe-shaped
// slice reproduced by its lobe, and shading with lobes against the path tracer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <cstdio>

#include <Eigen/Core>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "render/material.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "zonal/compare.h"
#include "zonal/lobes.h"
#include "zonal/projection.h"
#include "zonal/sh.h"
#include "zonal/shade.h"
#include "zonal/window.h"

namespace matlas::zonal {
namespace {

TEST(BandWindow, FactorsFollowTheirFormulas) {
  const int L = 7;
  for (BandWindow w : {BandWindow::none, BandWindow::hann, BandWindow::lanczos, BandWindow::gauss, BandWindow::taper}) {
    const std::vector<double> f = band_window(w, L);
    ASSERT_EQ(f.size(), 8u);
    EXPECT_EQ(f[0], 1.0) << band_window_name(w);  // the mean is kept
    for (int l = 1; l <= L; ++l) {
      EXPECT_LE(f[static_cast<std::size_t>(l)], f[static_cast<std::size_t>(l) - 1] + 1e-15);  // non-increasing
      EXPECT_GT(f[static_cast<std::size_t>(l)], 0.0);
    }
  }
  EXPECT_EQ(band_window(BandWindow::none, L)[7], 1.0);
  EXPECT_NEAR(band_window(BandWindow::hann, L)[4], 0.5, 1e-15);  // cos^2(pi / 4)
  EXPECT_NEAR(band_window(BandWindow::lanczos, L)[4], 2.0 / kPi, 1e-15);  // sin(pi / 2) / (pi / 2)
  EXPECT_NEAR(band_window(BandWindow::gauss, L)[2], std::exp(-6.0 / (2.0 * 3.2 * 3.2)), 1e-15);
  EXPECT_EQ(band_window(BandWindow::taper, L)[4], 1.0);                  // h = 4: the lower half kept
  EXPECT_NEAR(band_window(BandWindow::taper, L)[6], 0.5, 1e-15);         // cos^2(pi / 4)
  EXPECT_EQ(parse_band_window("lanczos"), BandWindow::lanczos);
  EXPECT_THROW(parse_band_window("hamming"), Error);
  EXPECT_THROW(band_window(BandWindow::hann, -1), Error);
}

/// The expansion of a delta at the pole shown with bands 0..L and a window: f(t) =
/// sum_l w_l Y_l^0(1) Y_l^0(t); its most negative value over its peak.
double delta_ringing(BandWindow window, int L) {
  const std::vector<double> w = band_window(window, L);
  std::vector<double> y, y1;
  zonal_harmonics(L, 1.0, y1);
  double lowest = 0, peak = 0;
  for (int s = 0; s <= 20000; ++s) {
    zonal_harmonics(L, std::cos(kPi * s / 20000.0), y);
    double f = 0;
    for (int l = 0; l <= L; ++l) f += w[static_cast<std::size_t>(l)] * y1[static_cast<std::size_t>(l)] * y[static_cast<std::size_t>(l)];
    lowest = std::min(lowest, f);
    peak = std::max(peak, f);
  }
  return lowest / peak;
}

TEST(BandWindow, TruncatedDeltaRingsOnlyWithoutAWindow) {
  for (int L : {4, 8, 16, 32}) {
    const double none = delta_ringing(BandWindow::none, L), hann = delta_ringing(BandWindow::hann, L),
                 lanczos = delta_ringing(BandWindow::lanczos, L), gauss = delta_ringing(BandWindow::gauss, L),
                 taper = delta_ringing(BandWindow::taper, L);
    std::printf("L = %d: most negative / peak: none %.4f hann %.5f lanczos %.5f gauss %.6f taper %.5f\n", L, none,
                hann, lanczos, gauss, taper);
    // The taper (Hann over the upper half) removes less of it: -0.12 .. -0.10 measured.
    EXPECT_LT(std::abs(taper), std::abs(none)) << L;
    EXPECT_GT(std::abs(taper), std::abs(hann)) << L;
    // Measured (this file's printout): none -0.15 .. -0.13, hann -0.038 .. -0.022, lanczos
    // -0.056 .. -0.037, gauss -0.011 .. -0.005 for L = 4 .. 32. On the sphere the windows do not
    // remove the negative lobes entirely (the (2l + 1) weights), but divide them by 3 to 25.
    EXPECT_LT(none, -0.10) << L;  // the box's side lobes: the test can fail
    EXPECT_GT(hann, -0.04) << L;
    EXPECT_GT(lanczos, -0.06) << L;
    EXPECT_GT(gauss, -0.012) << L;
    EXPECT_LT(std::abs(gauss), std::abs(hann)) << L;
    EXPECT_LT(std::abs(hann), std::abs(lanczos)) << L;
  }
}

TEST(Lobes, LegendreCoefficientsMatchAQuadratureInTheta) {
  // k_l = 2 pi integral_0^pi K(cos theta) P_l(cos theta) sin theta dtheta, by the midpoint rule
  // in theta (another variable than the implementation's), and the asymptotic exp(-l(l+1)/2kappa).
  for (double kappa : {4.0, 64.0, 1024.0}) {
    const int L = 40;
    const std::vector<double> k = lobe_legendre(kappa, L);
    EXPECT_NEAR(k[0], 1.0, 1e-8) << kappa;
    const int steps = 400000;
    std::vector<double> q(static_cast<std::size_t>(L) + 1, 0.0), y;
    for (int s = 0; s < steps; ++s) {
      const double theta = kPi * (s + 0.5) / steps;
      zonal_harmonics(L, std::cos(theta), y);
      for (int l = 0; l <= L; ++l)
        q[static_cast<std::size_t>(l)] += 2 * kPi * lobe_value(kappa, std::cos(theta)) * y[static_cast<std::size_t>(l)] /
                                          std::sqrt((2 * l + 1) / (4 * kPi)) * std::sin(theta) * kPi / steps;
    }
    for (int l : {1, 2, 10, 40}) {
      EXPECT_NEAR(k[static_cast<std::size_t>(l)], q[static_cast<std::size_t>(l)], 1e-6) << kappa << " l " << l;
      if (kappa >= 64) {
        EXPECT_NEAR(k[static_cast<std::size_t>(l)], std::exp(-l * (l + 1) / (2 * kappa)), 0.02) << l;
      }
    }
    // k_1 is the lobe's mean cosine, coth(kappa) - 1/kappa.
    EXPECT_NEAR(k[1], 1 / std::tanh(kappa) - 1 / kappa, 1e-9) << kappa;
  }
  // The cosine-weighted lobe's mass against a midpoint rule over the sphere.
  for (double kappa : {16.0, 256.0})
    for (double angle : {0.0, 0.7, 1.4, kPi / 2}) {
      const Vec3 r(-std::sin(angle), 0, std::cos(angle));
      double sum = 0;
      const int n = 2000;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < 2 * n; ++b) {
          const double theta = (a + 0.5) * kPi / (2 * n), phi = (b + 0.5) * kPi / n;
          const Vec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
          sum += lobe_value(kappa, r.dot(w)) * w.z() * std::sin(theta) * (kPi / (2 * n)) * (kPi / n);
        }
      EXPECT_NEAR(lobe_cosine_mass(kappa, r.z()), sum, 2e-4) << kappa << " " << angle;
    }
  EXPECT_NEAR(lobe_cosine_mass(4096, 0.5), 0.5, 1e-3);  // a sharp lobe: the cosine at its axis
  EXPECT_NEAR(lobe_product(64, 64), 64 / (4 * kPi) * (1 + std::exp(-256.0)), 1e-9);  // N^2 2pi/(2 kappa) for large kappa
  EXPECT_THROW(validate_lobes({64, 16}), Error);
  EXPECT_THROW(validate_lobes({0.5}), Error);
}

/// A lat-long map of the linear radiance c0 + c . w (as test_shade.cpp's).
Image linear_map(int width, int height, double c0, const Vec3& c) {
  Image map(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double theta = kPi * (y + 0.5) / height, phi = 2 * kPi * ((x + 0.5) / width - 0.5);
      const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      float* p = map.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<float>(c0 + c.dot(d));
    }
  return map;
}

TEST(Lobes, MapsOfALinearEnvironmentAreItsMeanCosineGradient) {
  // integral (c0 + c.w) K(d.w) dw = c0 + k_1 c.d, k_1 = coth(kappa) - 1/kappa.
  const Vec3 c(0.3, 0.7, -0.2);
  PrefilterSettings s;
  s.bands = 2;
  s.lobes = {16.0, 256.0};
  s.lobe_bands = 64;
  s.lobe_rows = 129;
  const PrefilteredEnvironment env(render::Environment(linear_map(256, 128, 1.5, c)), s);
  for (const Vec3& raw : {Vec3(0, 1, 0), Vec3(0.3, -0.5, 0.8), Vec3(-1, 0.1, 0.2), Vec3(0, -1, 0)}) {
    const Vec3 d = raw.normalized();
    for (std::size_t i = 0; i < 2; ++i) {
      const double kappa = s.lobes[i], k1 = 1 / std::tanh(kappa) - 1 / kappa;
      // The map is piecewise constant (256 x 128 texels): not exactly linear, 0.2 % off at kappa 256.
      EXPECT_NEAR(env.lobe_lookup(i, d)[0], 1.5 + k1 * c.dot(d), 5e-3) << kappa;
    }
  }
}

/// The BRDF `amplitude` K_kappa(r . wi) (r the mirror direction): its cosine-weighted slice is
/// amplitude Kc, one of the fitted functions.
struct LobeBrdf {
  double kappa, amplitude;
  Rgb operator()(const Vec3& wi, const Vec3& wo) const {
    if (wi.z() <= 0 || wo.z() <= 0) return Rgb::Zero();
    const Vec3 r(-wo.x(), -wo.y(), wo.z());
    return Rgb::Constant(amplitude * lobe_value(kappa, r.dot(wi)));
  }
};

/// Relative L2 error of a reconstructed slice over the upper hemisphere at theta_o.
double slice_error(const ZonalProjector& p, const ZonalCoefficients& c, const LobeBrdf& f, double theta_o) {
  const Vec3 wo(std::sin(theta_o), 0, std::cos(theta_o));
  double err = 0, ref = 0;
  for (int a = 0; a < 90; ++a)
    for (int b = 0; b < 180; ++b) {
      const double theta = (a + 0.5) * kPi / 180, phi = (b + 0.5) * kPi / 90;
      const Vec3 wi(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const double want = f(wi, wo)[0] * wi.z(), got = reconstruct(p.basis(), c, theta_o, wi)[0];
      err += (got - want) * (got - want) * std::sin(theta);
      ref += want * want * std::sin(theta);
    }
  return std::sqrt(err / ref);
}

TEST(Lobes, ALobeShapedSliceIsCarriedByItsLobe) {
  // The slice is 0.8 K_256 cos(theta_i) around the mirror direction: the fit puts about 0.8 on
  // lobe 256 (stored times the lobe's mass) and reconstructs the slice far better than the
  // expansion alone at the same L.
  const LobeBrdf f{256.0, 0.8};
  const BrdfTable table = tabulate(f);
  ProjectionSettings plain;
  plain.bands = 8;
  plain.theta_o_count = 16;
  ProjectionSettings with = plain;
  with.lobes = {64.0, 256.0, 1024.0};
  const ZonalProjector p0(plain), p1(with);
  const ZonalCoefficients c0 = p0.project(table), c1 = p1.project(table);
  ASSERT_EQ(c1.size(), c1.zonal_size() + 3);
  for (int t : {2, 6, 9}) {
    const double theta_o = ZonalCoefficients::theta_o(t, 16);
    const double e0 = slice_error(p0, c0, f, theta_o), e1 = slice_error(p1, c1, f, theta_o);
    const Rgb weight = c1.at(t, c1.zonal_size() + 1) / lobe_cosine_mass(256.0, std::cos(theta_o));
    std::printf("theta_o %.1f deg: slice error %.3f without lobes, %.3f with; lobe weights %.3f %.3f %.3f\n",
                theta_o * 180 / kPi, e0, e1, c1.at(t, c1.zonal_size())[0], weight[0], c1.at(t, c1.zonal_size() + 2)[0]);
    EXPECT_GT(e0, 0.3);  // 9 bands cannot hold a 3.6-degree lobe
    EXPECT_LT(e1, 0.02);  // measured 0.002 .. 0.004
    EXPECT_NEAR(weight[0], 0.8, 0.03);
  }
}

TEST(Lobes, NonnegativeMinimiserMeetsTheOptimalityConditions) {
  // Random positive definite G and right-hand sides: c >= 0, the gradient G c - r is 0 where c > 0
  // and >= 0 where c = 0 (KKT; the problem is strictly convex, so this is the minimiser).
  std::srand(7);
  int constrained = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Index M = 1 + trial % 8;
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(M, M);
    const Eigen::MatrixXd G = A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(M, M);
    const Eigen::VectorXd r = Eigen::VectorXd::Random(M);
    const Eigen::VectorXd c = nonnegative_minimiser(G, r);
    const Eigen::VectorXd gradient = G * c - r;
    for (Eigen::Index i = 0; i < M; ++i) {
      ASSERT_GE(c(i), 0.0);
      if (c(i) > 0) EXPECT_NEAR(gradient(i), 0.0, 1e-9) << "trial " << trial;
      else EXPECT_GE(gradient(i), -1e-9) << "trial " << trial;
    }
    if (c.minCoeff() == 0.0) ++constrained;
  }
  EXPECT_GT(constrained, 50);  // the bounds were active in many trials
}

TEST(Lobes, WeightsAreNeverNegative) {
  // A near-mirror conductor (alpha 0.02, sharper than the sharpest lobe) and a glossy plastic: an
  // unconstrained fit gives such peaks lobes of negative weight (holes that only the finest bands
  // cancel); the stored weights are >= 0 and the slice is still reproduced far better than by
  // the expansion alone.
  ProjectionSettings plain;
  plain.bands = 8;
  plain.theta_o_count = 8;
  ProjectionSettings with = plain;
  with.lobes = kDefaultLobes;
  const ZonalProjector p0(plain), p1(with);
  for (const BrdfTable& table : {tabulate(GgxConductor{Rgb(0.9, 0.9, 0.9), 0.02}),
                                 tabulate(RoughPlastic{Rgb(0.5, 0.3, 0.2), 0.05, 1.5, 1.0})}) {
    const ZonalCoefficients c = p1.project(table);
    for (int t = 0; t < c.theta_o_count; ++t)
      for (std::size_t i = 0; i < c.lobes.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) EXPECT_GE(c.at(t, c.zonal_size() + i)[ch], 0.0);
  }
}

TEST(Lobes, ProjectManyEqualsProjectWithLobes) {
  ProjectionSettings s;
  s.bands = 6;
  s.theta_o_count = 4;
  s.lobes = {64.0, 512.0};
  const ZonalProjector p(s);
  const BrdfTable a = tabulate(RoughPlastic{Rgb(0.5, 0.2, 0.1), 0.08, 1.5, 1.0});
  const BrdfTable b = tabulate(GgxConductor{Rgb(1.0, 0.8, 0.4), 0.1});
  const std::vector<ZonalCoefficients> many = p.project_many(
      [&](std::uint32_t bin, int channel, double* out) {
        out[0] = a.bin_rgb(bin)[channel];
        out[1] = b.bin_rgb(bin)[channel];
      },
      2);
  const ZonalCoefficients one = p.project(b);
  ASSERT_EQ(many[1].values.size(), one.values.size());
  double scale = 0, diff = 0;
  for (std::size_t v = 0; v < one.values.size(); ++v) {
    scale = std::max(scale, std::abs(one.values[v]));
    diff = std::max(diff, std::abs(one.values[v] - many[1].values[v]));
  }
  EXPECT_LT(diff, 1e-9 * scale);
  EXPECT_EQ(many[0].lobes, s.lobes);
}

TEST(Lobes, ShadingWithLobesIsCloserToTheRendererForAGlossyConductor) {
  // GGX aluminium-like conductor, alpha 0.1, under the synthetic environment's small sun: the
  // expansion at L = 8 misses the highlight, the lobes carry it.
  const BrdfTable table = tabulate(GgxConductor{Rgb(0.9, 0.9, 0.92), 0.1});
  render::SceneDescription desc;
  desc.environment = "test";
  const render::Scene scene(desc, std::nullopt, render::Environment(test::synthetic_environment(), 40.0));
  render::RenderSettings rs;
  rs.width = rs.height = 32;
  rs.spp = 512;
  const Image reference = render::render(scene, render::TableMaterial(table), rs);
  rs.seed = 2;
  const Image reference2 = render::render(scene, render::TableMaterial(table), rs);
  const std::vector<float> coverage = render::object_coverage(scene, rs);
  ShadeSettings ss;
  ss.width = ss.height = 32;
  ss.subsamples = 2;
  double errors[2];
  for (int with = 0; with < 2; ++with) {
    ProjectionSettings ps;
    ps.bands = 8;
    ps.theta_o_count = 16;
    if (with) ps.lobes = kDefaultLobes;
    const ZonalProjector projector(ps);
    PrefilterSettings fs;
    fs.bands = 8;
    fs.lobes = ps.lobes;
    fs.lobe_bands = 128;
    fs.lobe_rows = 129;
    const PrefilteredEnvironment env(scene.environment(), fs);
    const ImageErrors e = compare_to_reference(shade_image(scene, projector.basis(), projector.project(table), env, ss),
                                               reference, reference2, coverage);
    std::printf("L = 8 %s lobes: l1 %.4f rms %.4f noise %.4f\n", with ? "with" : "without", e.l1, e.rms, e.noise);
    errors[with] = e.rms;
  }
  EXPECT_GT(errors[0], 0.1);
  EXPECT_LT(errors[1], 0.25 * errors[0]);  // measured 0.235 -> 0.037
}

TEST(Lobes, ShadingRefusesCoefficientsAndMapsOfOtherLobes) {
  ProjectionSettings ps;
  ps.bands = 2;
  ps.theta_o_count = 2;
  ps.lobes = {64.0};
  const ZonalProjector p(ps);
  const ZonalCoefficients c = p.project(tabulate(Lambertian{Rgb::Constant(0.5)}));
  PrefilterSettings fs;
  fs.bands = 2;
  const PrefilteredEnvironment env(render::Environment::constant(Rgb::Ones()), fs);
  EXPECT_THROW(shade_point(p.basis(), c, env, Vec3(0, 1, 0), Vec3(0, 1, 0)), Error);
}

}  // namespace
}  // namespace matlas::zonal
