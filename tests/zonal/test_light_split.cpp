// The direct lights (zonal/light_split.h): the split moves exactly the brightest texels (or blocks)
// out of the map, the lights and the residual add up to the map, a constant environment has none,
// and shading the lights is sum f(wi, wo) power cos in the frame of the normal. With the
// residual's zonal shading, a sphere under a map of a few small bright lights comes out as the
// path tracer renders it, where the zonal shading alone does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "render/material.h"
#include "render/render.h"
#include "render/sampling.h"
#include "render/scene.h"
#include "zonal/compare.h"
#include "zonal/light_split.h"
#include "zonal/light_table.h"
#include "zonal/projection.h"
#include "zonal/shade.h"

namespace matlas::zonal {
namespace {

double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/// A dim, smooth sky with `spots` small very bright squares of 2 x 2 texels.
Image studio_like_map(int w, int h, int spots) {
  Image map(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = map.pixel(x, y);
      const double v = 0.05 + 0.05 * std::cos(kPi * y / h);
      p[0] = static_cast<float>(v);
      p[1] = static_cast<float>(0.8 * v);
      p[2] = static_cast<float>(0.6 * v);
    }
  for (int s = 0; s < spots; ++s) {
    const int x0 = (7 + 13 * s) % (w - 2), y0 = h / 5 + (5 * s) % (h / 2);
    for (int y = y0; y < y0 + 2; ++y)
      for (int x = x0; x < x0 + 2; ++x) {
        float* p = map.pixel(x, y);
        p[0] = 400.0f + 50.0f * static_cast<float>(s);
        p[1] = 380.0f;
        p[2] = 300.0f;
      }
  }
  return map;
}

/// Integral of the luminance over the sphere, texel by texel (exact row solid angles).
double luminance_integral(const Image& map) {
  double total = 0;
  for (int y = 0; y < map.height; ++y) {
    const double omega = (std::cos(kPi * y / map.height) - std::cos(kPi * (y + 1) / map.height)) * 2 * kPi / map.width;
    for (int x = 0; x < map.width; ++x) {
      const float* p = map.pixel(x, y);
      total += luminance(Rgb(p[0], p[1], p[2])) * omega;
    }
  }
  return total;
}

TEST(LightSplit, MovesTheBrightestTexelsAndKeepsTheRestExactly) {
  const Image map = studio_like_map(64, 32, 3);
  const render::Environment env(map, 30.0);
  LightSplitSettings s;
  s.max_texels = 100;
  const LightSplit split = split_lights(env, s);
  EXPECT_EQ(split.texels, 12);  // the 3 spots' 12 texels; the sky is far below 8x the mean
  EXPECT_EQ(split.points.size(), 12u);
  // Residual: 0 where a light was, the map elsewhere.
  int zeros = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const float* a = map.pixel(x, y);
      const float* b = split.residual.map().pixel(x, y);
      if (a[0] > 100.0f) {
        EXPECT_EQ(b[0] + b[1] + b[2], 0.0f);
        ++zeros;
      } else {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c], b[c]);
      }
    }
  EXPECT_EQ(zeros, 12);
  // Lights + residual = the map: in power, and the fraction reported.
  double light_power = 0;
  for (const LightPoint& p : split.points) light_power += luminance(p.power);
  const double total = luminance_integral(map), rest = luminance_integral(split.residual.map());
  EXPECT_NEAR(light_power + rest, total, 1e-9 * total);
  EXPECT_NEAR(split.light_fraction, light_power / total, 1e-9);
  EXPECT_GT(split.light_fraction, 0.5);
  // Each point lies in its texel's direction: the rotation applies (the residual keeps it too).
  for (const LightPoint& p : split.points) {
    EXPECT_NEAR(p.direction.norm(), 1.0, 1e-12);
    EXPECT_GT(luminance(env.eval(p.direction)), 100.0);
  }
  EXPECT_DOUBLE_EQ(split.residual.rotation(), env.rotation());
}

TEST(LightSplit, HonoursTheCountTheRatioAndBlocks) {
  const render::Environment env(studio_like_map(64, 32, 3));
  LightSplitSettings s;
  s.max_texels = 5;
  const LightSplit few = split_lights(env, s);
  EXPECT_EQ(few.texels, 5);
  double weakest_moved = 1e300;
  for (const LightPoint& p : few.points) weakest_moved = std::min(weakest_moved, luminance(env.eval(p.direction)));
  // Every texel left is at most as bright as the weakest one moved.
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const float* p = few.residual.map().pixel(x, y);
      EXPECT_LE(luminance(Rgb(p[0], p[1], p[2])), weakest_moved);
    }
  s.max_texels = 100;
  s.ratio = 1e6;  // no texel is a million times the mean
  EXPECT_TRUE(split_lights(env, s).points.empty());
  // Blocks of 2 x 2: each spot (aligned at even texels or not) is one or more blocks, one point
  // each, carrying the blocks' whole power.
  s.ratio = 8.0;
  s.merge = 2;
  const LightSplit blocks = split_lights(env, s);
  EXPECT_GE(blocks.points.size(), 3u);
  EXPECT_LE(blocks.points.size(), 12u);
  EXPECT_EQ(blocks.texels, 4 * static_cast<int>(blocks.points.size()));
  double power = 0;
  for (const LightPoint& p : blocks.points) power += luminance(p.power);
  EXPECT_NEAR(power, blocks.light_fraction * luminance_integral(env.map()), 1e-9 * power);
  // No lights from a constant environment; settings out of range are refused.
  EXPECT_TRUE(split_lights(render::Environment::constant(Rgb::Constant(2.0)), s).points.empty());
  s.merge = 0;
  EXPECT_THROW(split_lights(env, s), Error);
}

TEST(LightSplit, ShadingIsTheBrdfTimesPowerAndCosineInTheNormalsFrame) {
  const RoughPlastic plastic{Rgb(0.3, 0.2, 0.1), 0.2, 1.5, 1.0};
  const render::FunctionMaterial material([&](const Vec3& wi, const Vec3& wo) { return plastic(wi, wo); });
  const Vec3 n = Vec3(0.3, 0.8, 0.2).normalized(), wo = Vec3(0.1, 0.5, 0.9).normalized();
  const std::vector<LightPoint> points{{Vec3(0.5, 0.7, -0.1).normalized(), Rgb(2.0, 1.0, 0.5)},
                                       {Vec3(-0.2, 0.3, 0.9).normalized(), Rgb(0.3, 0.3, 0.3)},
                                       {-n, Rgb(100.0, 100.0, 100.0)}};  // below the horizon: nothing
  // Independently: another tangent frame (the BRDF is isotropic).
  const Vec3 t = n.cross(Vec3(1, 0, 0)).normalized(), b = n.cross(t);
  auto local = [&](const Vec3& v) { return Vec3(t.dot(v), b.dot(v), n.dot(v)); };
  Rgb expected = Rgb::Zero();
  for (int i = 0; i < 2; ++i)
    expected += plastic(local(points[static_cast<std::size_t>(i)].direction), local(wo)) *
                points[static_cast<std::size_t>(i)].power * n.dot(points[static_cast<std::size_t>(i)].direction);
  const Rgb got = shade_lights(points, material, n, wo);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-12 * expected.maxCoeff());
  EXPECT_EQ(shade_lights(points, material, n, -n).maxCoeff(), 0.0);  // seen from below
}

TEST(LightSplit, ASphereUnderSmallBrightLightsMatchesThePathTracer) {
  // A glossy plastic under a dim sky with three small bright spots: the zonal shading of the map
  // blurs and misplaces the highlights; with the spots as lights it follows the path tracer.
  const Image map = studio_like_map(128, 64, 3);
  const RoughPlastic plastic{Rgb(0.2, 0.2, 0.2), 0.08, 1.5, 1.0};
  const BrdfTable table = tabulate(plastic);
  const LightTable light_table = LightTable::reduce(table);
  render::SceneDescription desc;
  desc.environment = "constant";
  const render::Scene scene(desc, std::nullopt, render::Environment(map));
  render::RenderSettings rs;
  rs.width = rs.height = 24;
  rs.spp = 512;
  const render::TableMaterial material(table);
  const Image r1 = render::render(scene, material, rs);
  rs.seed = 2;
  const Image r2 = render::render(scene, material, rs);
  const std::vector<float> coverage = render::object_coverage(scene, rs);

  const ZonalProjector projector(ProjectionSettings{8, 16, 64, 128, kDefaultLobes});
  const ZonalCoefficients c = projector.project(table);
  PrefilterSettings fs;
  fs.bands = 8;
  fs.lobes = kDefaultLobes;
  ShadeSettings ss;
  ss.width = ss.height = 24;
  ss.subsamples = 4;
  const Image zonal_only = shade_image(scene, projector.basis(), c, PrefilteredEnvironment(scene.environment(), fs), ss);
  const LightSplit split = split_lights(scene.environment(), LightSplitSettings{});
  const LightTableMaterial lights_material(light_table);
  const DirectLights direct{&split.points, &lights_material};
  const Image with_lights = shade_image(scene, projector.basis(), c, PrefilteredEnvironment(split.residual, fs), ss, &direct);
  const double before = compare_to_reference(zonal_only, r1, r2, coverage).rms;
  const double after = compare_to_reference(with_lights, r1, r2, coverage).rms;
  EXPECT_LT(after, 0.05) << "before " << before;
  EXPECT_LT(after, 0.5 * before);
}

}  // namespace
}  // namespace matlas::zonal
