// ProgressiveRender: the mean of its passes converges to the exact image, its error estimate (from
// two independent halves) agrees with the error against an independent reference, time budgets
// and convergence stop it, and a cancelled pass leaves the state as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "brdf/analytic.h"
#include "core/error.h"
#include "render/progressive_render.h"
#include "render_test_util.h"

namespace matlas::render {
namespace {

constexpr double kProgressivePi = 3.14159265358979323846;

std::shared_ptr<const Scene> progressive_furnace() {
  SceneDescription d;
  d.constant_radiance = Rgb::Constant(1.0);
  return std::make_shared<const Scene>(d);
}

std::shared_ptr<const Material> progressive_white() {
  return std::make_shared<FunctionMaterial>([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(1.0 / kProgressivePi); });
}

std::shared_ptr<const Material> progressive_gold() {
  return std::make_shared<FunctionMaterial>(
      [g = GgxConductor{Rgb(0.95, 0.64, 0.54), 0.15}](const Vec3& wi, const Vec3& wo) { return g(wi, wo); });
}

ProgressiveSettings progressive_settings(int side, int first_spp, std::uint64_t seed = 1) {
  ProgressiveSettings s;
  s.render.width = s.render.height = side;
  s.render.spp = first_spp;
  s.render.seed = seed;
  s.adaptive.enabled = false;  // the passes' bookkeeping here; adaptive sampling: test_adaptive_sampling.cpp
  return s;
}

TEST(ProgressiveRender, ConvergesToTheFurnaceImage) {
  // A white Lambertian under uniform radiance 1 reflects exactly 1 everywhere on the object.
  ProgressiveSettings s = progressive_settings(24, 4);
  s.limits.target_error = 0.005;
  s.limits.min_converged_spp = 16;
  ProgressiveRender r(progressive_furnace(), progressive_white(), s);
  RefinementState state;
  for (int i = 0; i < 200 && !state.converged; ++i) state = r.refine(0.05);
  ASSERT_TRUE(state.converged) << state.spp << " spp, error " << state.relative_error;
  EXPECT_LE(state.relative_error, 0.005);
  EXPECT_GE(state.spp, 16);
  Image exact(24, 24);
  std::fill(exact.rgb.begin(), exact.rgb.end(), 1.0f);
  EXPECT_LT(test::object_relative_rms(r.image(), exact, r.object_pixels()), 3 * 0.005);
  // Once converged, refine adds nothing.
  const RefinementState again = r.refine(1.0);
  EXPECT_EQ(again.spp, state.spp);
  EXPECT_EQ(again.passes, state.passes);
}

TEST(ProgressiveRender, ErrorEstimateAgreesWithTheErrorAgainstAReference) {
  // A glossy conductor under a sky with a small sun: noisy at few samples. The reference is an
  // independent refinement (other seeds) with 64x the samples; its own error is removed in
  // quadrature.
  ProgressiveSettings rs = progressive_settings(24, 256, 777);
  rs.limits.max_pass_spp = 256;
  rs.limits.max_spp = 4096;
  rs.limits.target_error = 1e-9;
  ProgressiveRender reference(test::sky_scene(), progressive_gold(), rs);
  while (!reference.state().converged) reference.refine(10.0);
  ASSERT_EQ(reference.state().spp, 4096);
  const double reference_error = reference.state().relative_error;

  ProgressiveSettings s = progressive_settings(24, 16);
  s.limits.max_pass_spp = 16;
  s.limits.target_error = 1e-9;
  ProgressiveRender r(test::sky_scene(), progressive_gold(), s);
  for (int pass = 0; pass < 4; ++pass) r.refine(0.0);  // one pass per call
  const RefinementState state = r.state();
  ASSERT_EQ(state.passes, 4);
  ASSERT_EQ(state.spp, 64);
  const double measured = test::object_relative_rms(r.image(), reference.image(), r.object_pixels());
  const double actual = std::sqrt(std::max(0.0, measured * measured - reference_error * reference_error));
  EXPECT_GT(state.relative_error, 0.005) << "the test scene must be noisy at 64 spp";
  EXPECT_GT(state.relative_error, 0.6 * actual);
  EXPECT_LT(state.relative_error, 1.6 * actual);
  // More samples, less error: at 16x the samples about a quarter (RQMC may do better).
  for (int i = 0; i < 60 && r.state().spp < 1024; ++i) r.refine(0.0);
  EXPECT_LT(r.state().relative_error, 0.4 * state.relative_error);
}

TEST(ProgressiveRender, PassesGrowWithinTheTimeAndTheHalvesStayBalanced) {
  ProgressiveSettings s = progressive_settings(16, 4);
  s.limits.target_error = 1e-9;
  s.limits.max_spp = 256;
  s.limits.max_pass_spp = 64;
  ProgressiveRender r(test::sky_scene(), progressive_gold(), s);
  EXPECT_EQ(r.refine(0.0).spp, 4);  // the first pass is the settings' spp
  EXPECT_EQ(r.state().relative_error, std::numeric_limits<double>::infinity());  // one half only
  const RefinementState second = r.refine(0.0);
  EXPECT_EQ(second.passes, 2);
  EXPECT_TRUE(std::isfinite(second.relative_error));
  // Given time, passes double up to max_pass_spp and stop at max_spp.
  RefinementState state;
  for (int i = 0; i < 100 && !state.converged; ++i) state = r.refine(5.0);
  EXPECT_TRUE(state.converged);
  EXPECT_EQ(state.spp, 256);
}

struct ProgressiveThrowingSink final : ProgressSink {
  void update(const std::string&, std::uint64_t, std::uint64_t) override { throw std::runtime_error("cancelled"); }
  void message(const std::string&) override {}
  void finish(const std::string&) override {}
};

TEST(ProgressiveRender, ACancelledPassLeavesTheStateAsItWas) {
  ProgressiveRender r(test::sky_scene(), progressive_gold(), progressive_settings(16, 8));
  r.refine(0.0);
  const Image before = r.image();
  const RefinementState state = r.state();
  ProgressiveThrowingSink cancel;
  EXPECT_THROW(r.refine(1.0, cancel), std::runtime_error);
  EXPECT_EQ(r.state().spp, state.spp);
  EXPECT_EQ(r.state().passes, state.passes);
  EXPECT_EQ(r.image().rgb, before.rgb);
}

TEST(ProgressiveRender, InvalidSettingsAreRefused) {
  ProgressiveSettings s = progressive_settings(16, 8);
  s.limits.target_error = 0;
  EXPECT_THROW(ProgressiveRender(test::sky_scene(), progressive_gold(), s), Error);
  s = progressive_settings(16, 64);
  s.limits.max_spp = 32;
  EXPECT_THROW(ProgressiveRender(test::sky_scene(), progressive_gold(), s), Error);
  s = progressive_settings(16, 8);
  s.limits.max_pass_spp = 0;
  EXPECT_THROW(ProgressiveRender(test::sky_scene(), progressive_gold(), s), Error);
}

}  // namespace
}  // namespace matlas::render
