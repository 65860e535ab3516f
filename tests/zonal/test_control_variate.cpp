// The real-time shading as a control variate of the renderer (zonal/control_variate.h): its
// integral is the quadrature of its function against the environment, and a render with it is the
// render without it, with less noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "render/material.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "render/sampling.h"
#include "zonal/control_variate.h"
#include "zonal/projection.h"
#include "zonal/sh.h"

namespace matlas::zonal {
namespace {

struct PlasticUnderTheSyntheticSky {
  explicit PlasticUnderTheSyntheticSky(int bands, std::vector<double> lobes = kDefaultLobes)
      : table(tabulate(RoughPlastic{Rgb(0.5, 0.3, 0.2), 0.15, 1.5, 1.0})),
        environment(test::synthetic_environment(), 40.0) {
    ProjectionSettings ps;
    ps.bands = bands;
    ps.theta_o_count = 16;
    ps.lobes = lobes;
    coefficients = ZonalProjector(ps).project(table);
    PrefilterSettings fs;
    fs.bands = bands;
    fs.lobes = lobes;
    fs.lobe_bands = 128;
    fs.texels_per_band = 32;
    fs.lobe_rows = 1025;
    fs.supersample = 16;  // the synthetic map's texels are 11 degrees wide
    prefiltered = std::make_shared<const PrefilteredEnvironment>(environment, fs);
  }
  BrdfTable table;
  render::Environment environment;
  ZonalCoefficients coefficients;
  std::shared_ptr<const PrefilteredEnvironment> prefiltered;
};

/// integral over the sphere of L(w) g(w), g in the frame of n: each texel of the (piecewise
/// constant) map integrated by s x s midpoints, with their exact solid angles.
inline Rgb quadrature(const render::Environment& env, const ZonalControlVariate& cv, const Vec3& n, const Vec3& wo, int s) {
  Vec3 t, b;
  render::orthonormal_basis(n, t, b);
  const Vec3 wo_local(t.dot(wo), b.dot(wo), n.dot(wo));
  Rgb sum = Rgb::Zero();
  const int rows = env.height() * s, cols = env.width() * s;
  for (int y = 0; y < rows; ++y) {
    const double area = (std::cos(kPi * y / rows) - std::cos(kPi * (y + 1) / rows)) * 2 * kPi / cols;
    for (int x = 0; x < cols; ++x) {
      const Vec3 w = env.from_uv((x + 0.5) / cols, (y + 0.5) / rows);
      sum += env.eval(w) * cv.eval(Vec3(t.dot(w), b.dot(w), n.dot(w)), wo_local) * area;
    }
  }
  return sum;
}

TEST(ControlVariate, IntegralIsTheQuadratureOfTheFunction) {
  for (const bool lobes : {false, true}) {
    const PlasticUnderTheSyntheticSky s(8, lobes ? kDefaultLobes : std::vector<double>{});
    const ZonalControlVariate cv(s.coefficients, s.prefiltered);
    for (const auto& [n_raw, wo_raw] : {std::pair{Vec3(0, 1, 0), Vec3(0.2, 1, 0.1)}, std::pair{Vec3(0.3, 0.5, -0.8), Vec3(0.1, 0.4, -0.2)},
                                         std::pair{Vec3(1, 0.2, 0), Vec3(0.2, 1, 0.3)}}) {
      const Vec3 n = n_raw.normalized(), wo = wo_raw.normalized();
      const Rgb expected = quadrature(s.environment, cv, n, wo, 16);
      const Rgb got = cv.integral(n, wo);
      std::printf("lobes %d: integral %.5f %.5f %.5f quadrature %.5f %.5f %.5f\n", lobes, got[0], got[1], got[2], expected[0],
                  expected[1], expected[2]);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 2e-3 * expected.maxCoeff()) << c;
    }
  }
}

TEST(ControlVariate, APreviewWithItIsTheSameImageWithLessNoise) {
  // The plastic on a sphere under the synthetic sky: the control variate's render agrees with a
  // long plain reference (its bias: the maps' interpolation) and has a fraction of the plain
  // render's error at the same samples.
  const PlasticUnderTheSyntheticSky s(8);
  const auto scene = std::make_shared<const render::Scene>(render::SceneDescription{}, std::nullopt, s.environment);
  const render::TableMaterial material(s.table);
  render::RenderSettings rs;
  rs.width = rs.height = 32;
  rs.spp = 2048;
  rs.seed = 7;
  const Image reference = render::render(*scene, material, rs);
  rs.spp = 32;
  rs.seed = 1;
  const ZonalControlVariate cv(s.coefficients, s.prefiltered);
  const render::ControlGrid grid = render::control_grid(*scene, rs.width, rs.height, cv);
  Image plain;
  const Image controlled = render::render(*scene, material, rs, null_progress(), nullptr, {&cv, &grid, &plain});
  double e_plain = 0, e_cv = 0, norm = 0;
  int pixels = 0;
  for (std::size_t p = 0; p < grid.cells.size(); ++p) {
    if (grid.cells[p].subdivisions == 0) continue;
    ++pixels;
    for (int c = 0; c < 3; ++c) {
      const double r = reference.rgb[3 * p + c];
      e_plain += std::pow(plain.rgb[3 * p + c] - r, 2);
      e_cv += std::pow(controlled.rgb[3 * p + c] - r, 2);
      norm += r * r;
    }
  }
  e_plain = std::sqrt(e_plain / norm), e_cv = std::sqrt(e_cv / norm);
  std::printf("%d pixels: plain %.4f, control variate %.4f relative RMS against 2048 spp\n", pixels, e_plain, e_cv);
  EXPECT_GT(pixels, 400);
  EXPECT_GT(e_plain, 0.02);  // the plain render at 32 spp is visibly noisy: the comparison can fail
  EXPECT_LT(e_cv, 0.35 * e_plain);
}

}  // namespace
}  // namespace matlas::zonal
