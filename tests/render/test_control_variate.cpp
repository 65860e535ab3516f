// The renderer's control variate (render/control_variate.h): with the exact slice as g, every
// camera sample at the object returns G exactly (so the estimator's weights sum to one over the
// techniques, below the horizon included); with any g the image stays unbiased; the plain
// estimate of the same samples is the render without it; ProgressiveRender keeps the less noisy.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "render/progressive_render.h"
#include "render/render.h"
#include "render_test_util.h"

namespace matlas::render {
namespace {

constexpr double kCvPi = 3.14159265358979323846;

/// A Lambertian of albedo a under a constant environment L0: g = a / pi max(cos, 0) is the slice
/// itself, G = a L0 everywhere.
class ExactLambertian final : public ControlVariate {
public:
  ExactLambertian(double albedo, double radiance) : a_(albedo), l0_(radiance) {}
  Rgb smooth_integral(const Vec3&, const Vec3&) const override { return Rgb::Constant(a_ * l0_); }
  Rgb sharp_integral(const Vec3&, const Vec3&) const override { return Rgb::Zero(); }
  Rgb eval(const Vec3& wi, const Vec3&) const override { return Rgb::Constant(a_ / kCvPi * std::max(wi.z(), 0.0)); }

private:
  double a_, l0_;
};

/// A poor but valid control variate: a constant over the whole sphere, G = c 4 pi L0.
class ConstantControl final : public ControlVariate {
public:
  ConstantControl(double c, double radiance) : c_(c), l0_(radiance) {}
  Rgb smooth_integral(const Vec3&, const Vec3&) const override { return Rgb::Constant(c_ * 4 * kCvPi * l0_); }
  Rgb sharp_integral(const Vec3&, const Vec3&) const override { return Rgb::Zero(); }
  Rgb eval(const Vec3&, const Vec3&) const override { return Rgb::Constant(c_); }

private:
  double c_, l0_;
};

std::shared_ptr<const Scene> furnace(double radiance) {
  SceneDescription d;
  d.constant_radiance = Rgb::Constant(radiance);
  return std::make_shared<const Scene>(d);
}

RenderSettings small(int spp) {
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = spp;
  return s;
}

double object_mean(const Image& image, const std::vector<bool>& object) {
  double sum = 0;
  int n = 0;
  for (std::size_t p = 0; p < object.size(); ++p)
    if (object[p]) sum += image.rgb[3 * p], ++n;
  return sum / n;
}

TEST(RenderControlVariate, TheExactSliceMakesEverySampleExact) {
  const auto scene = furnace(1.5);
  const FunctionMaterial white([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.7 / kCvPi); });
  const ExactLambertian control(0.7, 1.5);
  const RenderSettings s = small(4);
  for (const bool with_grid : {false, true}) {
    const ControlGrid grid = control_grid(*scene, s.width, s.height, control);
    Image plain;
    const Image image = render(*scene, white, s, null_progress(), nullptr, {&control, with_grid ? &grid : nullptr, &plain});
    const std::vector<float> coverage = object_coverage(*scene, s);
    double plain_spread = 0;
    int checked = 0;
    for (std::size_t p = 0; p < coverage.size(); ++p) {
      if (coverage[p] < 1.0f) continue;
      // With the grid, silhouette pixels (a corner off the object) render plain: coverage 1 but
      // a corner outside happens only at the rim, skip those by the grid's own flag.
      if (with_grid && grid.cells[p].subdivisions == 0) continue;
      EXPECT_NEAR(image.rgb[3 * p], 0.7 * 1.5, 1e-6) << p;  // float storage
      plain_spread = std::max(plain_spread, std::abs(plain.rgb[3 * p] - 0.7 * 1.5));
      ++checked;
    }
    EXPECT_GT(checked, 200);
    EXPECT_GT(plain_spread, 1e-3);  // the plain estimate of the same samples is noisy: the test can fail
  }
}

TEST(RenderControlVariate, ThePlainEstimateIsTheRenderWithoutIt) {
  const auto scene = std::make_shared<const Scene>(SceneDescription{}, std::nullopt, Environment(test::synthetic_environment()));
  const FunctionMaterial white([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.5 / kCvPi); });
  const ConstantControl control(0.1, 1.0);
  Image plain;
  render(*scene, white, small(8), null_progress(), nullptr, {&control, nullptr, &plain});
  const Image reference = render(*scene, white, small(8));
  ASSERT_EQ(plain.rgb.size(), reference.rgb.size());
  for (std::size_t i = 0; i < plain.rgb.size(); ++i) EXPECT_EQ(plain.rgb[i], reference.rgb[i]) << i;
}

TEST(RenderControlVariate, APoorControlVariateStaysUnbiased) {
  // A constant g under a constant environment: the image's mean over the object agrees with the
  // plain one within their noise (many samples), though no sample is exact.
  const auto scene = furnace(1.0);
  const FunctionMaterial white([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.6 / kCvPi); });
  const ConstantControl control(0.08, 1.0);
  RenderSettings s = small(256);
  const std::vector<float> coverage = object_coverage(*scene, s);
  std::vector<bool> object(coverage.size());
  for (std::size_t p = 0; p < coverage.size(); ++p) object[p] = coverage[p] >= 1.0f;
  const Image image = render(*scene, white, s, null_progress(), nullptr, {&control, nullptr, nullptr});
  EXPECT_NEAR(object_mean(image, object), 0.6, 2e-3);
}

TEST(RenderControlVariate, ProgressiveRenderKeepsTheLessNoisyEstimate) {
  const auto scene = furnace(1.5);
  const auto white = std::make_shared<FunctionMaterial>([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.7 / kCvPi); });
  ProgressiveSettings s;
  s.render = small(8);
  s.limits.target_error = 1e-12;
  s.control_variate = [] { return std::make_shared<ExactLambertian>(0.7, 1.5); };
  s.adaptive.enabled = false;  // the choice alone (with adaptive sampling every trial restarts)
  ProgressiveRender good(scene, white, s);
  good.refine(1e-3);  // the first pass: plain, as fast as without a control variate
  EXPECT_FALSE(good.controlled());
  EXPECT_EQ(good.state().passes, 1);
  EXPECT_GT(good.state().spp, 0);
  good.refine(1e-3);  // the second: both estimates; the exact one wins and the refinement restarts from it
  EXPECT_TRUE(good.controlled());
  EXPECT_EQ(good.state().passes, 1);
  const std::vector<float> coverage = object_coverage(*scene, s.render);
  const Image image = good.image();
  int exact = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] >= 1.0f && std::abs(image.rgb[3 * p] - 0.7 * 1.5) < 1e-6) ++exact;
  EXPECT_GT(exact, 200);  // the plain first pass is gone from the mean
  good.refine(1e-3);
  EXPECT_EQ(good.state().passes, 2);
  // A control variate far from the slice (a large constant: its noise swamps the material's) is
  // dropped on the second pass, which then counts as a plain pass.
  s.control_variate = [] { return std::make_shared<ConstantControl>(3.0, 1.5); };
  ProgressiveRender poor(scene, white, s);
  poor.refine(1e-3);
  poor.refine(1e-3);
  EXPECT_FALSE(poor.controlled());
  EXPECT_EQ(poor.state().passes, 2);
}

TEST(RenderControlVariate, TheGridLeavesCreasesAndSilhouettesToThePlainEstimator) {
  // A flat-shaded cube: pixels inside a face are one cell, pixels across an edge (a 90-degree
  // turn of the normal) and on the silhouette render without the control variate.
  SceneDescription d;
  d.object = "cube";
  d.camera.position = Vec3(2.5, 2.0, 3.5);
  const Scene scene(d, test::flat_cube(), Environment::constant(Rgb::Constant(1.0)));
  const ConstantControl control(0.1, 1.0);
  const int side = 48;
  const ControlGrid grid = control_grid(scene, side, side, control);
  int inside = 0, across = 0;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      // The face of each corner's hit (the normals are per face).
      std::vector<Vec3> normals;
      for (const auto& [cx, cy] : {std::pair{x, y}, std::pair{x + 1, y}, std::pair{x, y + 1}, std::pair{x + 1, y + 1}}) {
        Vec3 o, dir;
        scene.camera_ray(cx, cy, side, side, &o, &dir);
        const auto hit = scene.intersect(o, dir);
        if (hit && hit->object) normals.push_back(hit->normal);
      }
      const int s = grid.cells[static_cast<std::size_t>(y * side + x)].subdivisions;
      if (normals.size() < 4) {
        EXPECT_EQ(s, 0) << x << " " << y;  // the silhouette
        continue;
      }
      bool one_face = true;
      for (const Vec3& n : normals) one_face = one_face && n.dot(normals[0]) > 0.999;
      if (one_face) {
        EXPECT_GE(s, 1) << x << " " << y;
        ++inside;
      } else {
        EXPECT_EQ(s, 0) << x << " " << y;
        ++across;
      }
    }
  EXPECT_GT(inside, 300);
  EXPECT_GT(across, 20);
}

TEST(RenderControlVariate, HalvesNoiseIsTheNoiseNotTheStructure) {
  // Two estimates of a strongly structured image (a ramp with an edge) that agree: no noise;
  // with independent +-0.1 errors on a level of 0.5: about 0.1 sqrt(2) / 0.5.
  Image a(16, 16), b(16, 16), c(16, 16);
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const float structure = (i % 48 < 24 ? 0.2f : 0.8f) + 0.01f * static_cast<float>(i % 7);
    a.rgb[i] = b.rgb[i] = structure;
    c.rgb[i] = 0.5f + ((i * 7919) % 13 < 6 ? 0.1f : -0.1f);
  }
  const std::vector<bool> all(256, true);
  EXPECT_EQ(halves_noise(a, b, all), 0.0);
  Image d(16, 16);
  for (std::size_t i = 0; i < d.rgb.size(); ++i) d.rgb[i] = 0.5f + ((i * 104729) % 11 < 5 ? 0.1f : -0.1f);
  EXPECT_NEAR(halves_noise(c, d, all), 0.1 * std::sqrt(2.0) / 0.5, 0.03);
}

}  // namespace
}  // namespace matlas::render
