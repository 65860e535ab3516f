// Prefiltered environments and rotated-ZH shading: exact cases and agreement with the renderer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "render/material.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "zonal/compare.h"
#include "zonal/projection.h"
#include "zonal/shade.h"

namespace matlas::zonal {
namespace {

const double kC0 = 1.5;
const Vec3 kC(0.3, 0.7, -0.2);

/// A lat-long map of the linear radiance c0 + c . w (texel centres), in the Environment's
/// convention (+y up, phi = 2 pi (u - 0.5)).
Image linear_map(int width, int height) {
  Image map(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double theta = kPi * (y + 0.5) / height, phi = 2 * kPi * ((x + 0.5) / width - 0.5);
      const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      float* p = map.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<float>(kC0 + kC.dot(d));
    }
  return map;
}

TEST(Prefilter, ConstantEnvironmentHasOnlyBandZero) {
  PrefilterSettings s;
  s.bands = 4;
  const PrefilteredEnvironment env(render::Environment::constant(Rgb(2.0, 1.0, 0.5)), s);
  const Vec3 d = Vec3(0.3, -0.5, 0.8).normalized();
  EXPECT_NEAR(env.lookup(0, d)[0], 2.0 * std::sqrt(4 * kPi), 1e-6);
  EXPECT_NEAR(env.lookup(0, d)[2], 0.5 * std::sqrt(4 * kPi), 1e-6);
  for (int l = 1; l <= 4; ++l) EXPECT_NEAR(env.lookup(l, d)[0], 0.0, 2e-3) << l;
}

TEST(Prefilter, LinearEnvironmentBandOneIsItsGradient) {
  // E_1(d) = integral (c0 + c.w) Y_1^0(d.w) dw = sqrt(3/4pi) (4pi/3) c.d ; E_2 = 0.
  PrefilterSettings s;
  s.bands = 3;
  const PrefilteredEnvironment env(render::Environment(linear_map(128, 64)), s);
  for (const Vec3& raw : {Vec3(0, 1, 0), Vec3(0.3, -0.5, 0.8), Vec3(-1, 0.1, 0.2), Vec3(0.2, 0.3, -0.9)}) {
    const Vec3 d = raw.normalized();
    const double e1 = std::sqrt(3 / (4 * kPi)) * (4 * kPi / 3) * kC.dot(d);
    EXPECT_NEAR(env.exact(1, d)[0], e1, 2e-3);
    EXPECT_NEAR(env.lookup(1, d)[0], e1, 1e-2);
    EXPECT_NEAR(env.lookup(0, d)[0], kC0 * std::sqrt(4 * kPi), 2e-3);
    EXPECT_NEAR(env.exact(2, d)[0], 0.0, 2e-3);
  }
}

TEST(Prefilter, RotationTurnsTheFilteredMaps) {
  PrefilterSettings s;
  s.bands = 2;
  const Image map = linear_map(128, 64);
  const PrefilteredEnvironment plain(render::Environment(map), s), turned(render::Environment(map, 90.0), s);
  // Environment rotation adds to phi = atan2(z, x): the direction d of the map is seen at R d.
  const Vec3 d = Vec3(0.6, 0.2, 0.3).normalized();
  const double c = std::cos(kPi / 2), sn = std::sin(kPi / 2);
  const Vec3 rd(c * d.x() - sn * d.z(), d.y(), sn * d.x() + c * d.z());
  EXPECT_NEAR(turned.exact(1, rd)[0], plain.exact(1, d)[0], 5e-3);
  EXPECT_GT(std::abs(turned.exact(1, d)[0] - plain.exact(1, d)[0]), 0.1);
}

TEST(Shade, LambertianUnderALinearEnvironmentIsExactFromOneBand) {
  // Irradiance of a linear environment: pi c0 + (2 pi / 3) c.n, so radiance = a (c0 + 2/3 c.n).
  const double a = 0.7;
  const render::Environment environment(linear_map(256, 128));
  for (int L : {1, 2, 5}) {
    ProjectionSettings ps;
    ps.bands = L;
    ps.theta_o_count = 8;
    const ZonalProjector projector(ps);
    const ZonalCoefficients coeffs = projector.project(tabulate(Lambertian{Rgb::Constant(a)}));
    PrefilterSettings s;
    s.bands = L;
    s.texels_per_band = 16;
    const PrefilteredEnvironment env(environment, s);
    for (const Vec3& raw : {Vec3(0, 1, 0), Vec3(0.3, -0.5, 0.8), Vec3(-1, 0.1, 0.2)}) {
      const Vec3 n = raw.normalized();
      const Vec3 wo = (n + Vec3(0.2, 0.1, 0.4)).normalized();
      const double expected = a * (kC0 + 2.0 / 3.0 * kC.dot(n));
      // L = 1 misses the clamped cosine's band 2, which sees nothing of a linear environment.
      EXPECT_NEAR(shade_point(projector.basis(), coeffs, env, n, wo)[1], expected, 3e-3 * expected) << L;
    }
  }
}

TEST(Shade, WindowScalesEachBandOfTheShading) {
  // The Lambertian under the linear environment again: radiance = a (c0 + w_1 2/3 c.n) with the
  // window's band-1 factor w_1 (band 2 and above see nothing of a linear environment).
  const double a = 0.7;
  const render::Environment environment(linear_map(256, 128));
  ProjectionSettings ps;
  ps.bands = 3;
  ps.theta_o_count = 8;
  const ZonalProjector projector(ps);
  const ZonalCoefficients coeffs = projector.project(tabulate(Lambertian{Rgb::Constant(a)}));
  PrefilterSettings s;
  s.bands = 3;
  s.texels_per_band = 16;
  const PrefilteredEnvironment env(environment, s);
  for (BandWindow window : {BandWindow::hann, BandWindow::lanczos, BandWindow::gauss}) {
    const std::vector<double> w = band_window(window, 3);
    for (const Vec3& raw : {Vec3(0, 1, 0), Vec3(0.3, -0.5, 0.8), Vec3(-1, 0.1, 0.2)}) {
      const Vec3 n = raw.normalized();
      const Vec3 wo = (n + Vec3(0.2, 0.1, 0.4)).normalized();
      const double expected = a * (kC0 + w[1] * 2.0 / 3.0 * kC.dot(n));
      EXPECT_NEAR(shade_point(projector.basis(), coeffs, env, n, wo, &w)[1], expected, 3e-3 * expected);
    }
  }
  // Showing bands 0..0 only: the mean, a c0, whatever the window.
  const std::vector<double> w0 = band_window(BandWindow::hann, 0);
  EXPECT_NEAR(shade_point(projector.basis(), coeffs, env, Vec3(0, 1, 0), Vec3(0, 1, 0), &w0)[1], a * kC0, 3e-3 * a * kC0);
}

TEST(Shade, MatchesTheRendererOnASphere) {
  RoughPlastic plastic;
  plastic.alpha = 0.3;
  plastic.diffuse = Rgb(0.5, 0.3, 0.2);
  const BrdfTable table = tabulate(plastic);
  render::SceneDescription desc;
  desc.environment = "test";
  const render::Scene scene(desc, std::nullopt, render::Environment(test::synthetic_environment(), 40.0));
  render::RenderSettings rs;
  rs.width = rs.height = 40;
  rs.spp = 1024;
  const Image reference = render::render(scene, render::TableMaterial(table), rs);
  rs.seed = 2;
  const Image reference2 = render::render(scene, render::TableMaterial(table), rs);
  const std::vector<float> coverage = render::object_coverage(scene, rs);
  ShadeSettings ss;
  ss.width = ss.height = 40;
  ss.subsamples = 4;
  double previous = 1e9;
  for (int L : {2, 6, 16}) {
    ProjectionSettings ps;
    ps.bands = L;
    const ZonalProjector projector(ps);
    PrefilterSettings fs;
    fs.bands = L;
    const PrefilteredEnvironment env(scene.environment(), fs);
    const ImageErrors e = compare_to_reference(shade_image(scene, projector.basis(), projector.project(table), env, ss),
                                               reference, reference2, coverage);
    std::printf("L = %d: l1 %.4f rms %.4f noise %.4f\n", L, e.l1, e.rms, e.noise);
    if (L == 2) {
      EXPECT_GT(e.rms, 0.02);  // two bands visibly miss the gloss: the comparison can fail
    }
    EXPECT_LE(e.rms, previous) << L;
    previous = e.rms;
  }
  EXPECT_LT(previous, 0.01);
}

TEST(Shade, RefusesGroundAndLights) {
  render::SceneDescription desc;
  desc.ground = true;
  const render::Scene scene(desc, std::nullopt, render::Environment::constant(Rgb::Ones()));
  const ZonalBasis basis(1);
  ZonalCoefficients c;
  c.bands = 1;
  c.theta_o_count = 1;
  c.values.assign(9, 0.0);
  PrefilterSettings s;
  s.bands = 1;
  const PrefilteredEnvironment env(scene.environment(), s);
  EXPECT_THROW(shade_image(scene, basis, c, env, ShadeSettings{}), Error);
}

}  // namespace
}  // namespace matlas::zonal
