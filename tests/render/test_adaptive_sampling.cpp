// Adaptive sampling (render/adaptive_sampling.h): the shares follow the estimated standard
// deviation of one sample, average one, respect the floor and the cap, spread over their window;
// a render takes them as its pixels' sample counts; and a progressive render that adapts stays
// unbiased (it converges to a uniform reference) while reaching a lower error at equal samples on
// a scene whose noise sits in a few pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

#include "brdf/analytic.h"
#include "core/error.h"
#include "render/adaptive_sampling.h"
#include "render/progressive_render.h"
#include "render/render.h"
#include "render_test_util.h"

namespace matlas::render {
namespace {

double mean_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size()); }

/// Two 16x16 estimates that agree except in the pixels given, where red differs by `d`.
void differing(Image& a, Image& b, const std::vector<std::pair<int, double>>& pixels) {
  a = Image(16, 16);
  b = Image(16, 16);
  std::fill(a.rgb.begin(), a.rgb.end(), 0.5f);
  std::fill(b.rgb.begin(), b.rgb.end(), 0.5f);
  for (const auto& [p, d] : pixels) b.rgb[3 * static_cast<std::size_t>(p)] += static_cast<float>(d);
}

TEST(AdaptiveSampling, SharesFollowTheStandardDeviationOfOneSample) {
  Image a, b;
  // Pixel 10 differs by 0.2 with 4 samples, pixel 20 by 0.1 with 16, pixel 30 by 0.1 with 4:
  // one sample's deviation is sqrt(n) |d| / 2 = 0.2, 0.2 and 0.1.
  differing(a, b, {{10, 0.2}, {20, 0.1}, {30, 0.1}});
  std::vector<int> samples(256, 4);
  samples[20] = 16;
  AdaptiveSampling s;
  s.radius = 0;
  s.floor = 0.01;
  s.cap = 4096;  // not binding here
  const std::vector<double> shares = adaptive_pixel_samples(a, b, samples, s);
  ASSERT_EQ(shares.size(), 256u);
  EXPECT_NEAR(mean_of(shares), 1.0, 1e-12);
  EXPECT_NEAR(shares[10] / shares[20], 1.0, 1e-5);  // (the images are float)
  EXPECT_NEAR(shares[10] / shares[30], 2.0, 1e-5);
  // Every noiseless pixel takes the floor; the three noisy ones share the rest.
  EXPECT_NEAR(shares[0], s.floor, 1e-9);
  EXPECT_NEAR(shares[255], s.floor, 1e-9);
  EXPECT_NEAR(shares[10] + shares[20] + shares[30], 256 - 253 * s.floor, 1e-6);
}

TEST(AdaptiveSampling, TheFloorAndTheCapBoundTheShares) {
  Image a, b;
  differing(a, b, {{100, 1.0}});  // all the noise in one pixel
  AdaptiveSampling s;
  s.radius = 0;
  s.floor = 0.25;
  s.cap = 8;
  const std::vector<double> shares = adaptive_pixel_samples(a, b, std::vector<int>(256, 4), s);
  EXPECT_NEAR(mean_of(shares), 1.0, 1e-12);
  // The cap binds the noisy pixel at cap / floor = 32 times every other pixel's share.
  // Even the cap there leaves the mean under 1: the shares are scaled up to mean 1.
  const double floor = 256.0 / (8.0 / 0.25 + 255.0);
  EXPECT_NEAR(shares[0], floor, 1e-9);
  EXPECT_NEAR(shares[100] / shares[0], 8.0 / 0.25, 1e-9);
}

TEST(AdaptiveSampling, TheWindowSpreadsOnePixelsNoiseToItsNeighbours) {
  Image a, b;
  differing(a, b, {{5 * 16 + 5, 0.5}});
  AdaptiveSampling s;
  s.radius = 1;
  s.floor = 0.01;
  const std::vector<double> shares = adaptive_pixel_samples(a, b, std::vector<int>(256, 4), s);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) EXPECT_NEAR(shares[(5 + dy) * 16 + 5 + dx], shares[5 * 16 + 5], 1e-12);
  EXPECT_LT(shares[5 * 16 + 7], shares[5 * 16 + 6]);  // outside the window: the floor
}

TEST(AdaptiveSampling, NoNoiseMeansEvenShares) {
  Image a, b;
  differing(a, b, {});
  const std::vector<double> shares = adaptive_pixel_samples(a, b, std::vector<int>(256, 4));
  for (const double share : shares) EXPECT_EQ(share, 1.0);
}

TEST(AdaptiveSampling, ShownWeightsFollowTheToneCurvesSlope) {
  // The clamp curve at exposure 0, then sRGB: slope 12.92 in sRGB's linear toe (v < 0.0031308),
  // 0 past 1 (clamped); the linear term 1 / sum v^2 everywhere.
  Image image(3, 1);
  const float values[3] = {0.001f, 0.5f, 5.0f};
  for (int p = 0; p < 3; ++p)
    for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = values[p];
  const std::vector<double> w = linear_and_shown_weights(image, {true, true, true}, ToneMap{ToneMap::Curve::clamp, 0.0});
  ASSERT_EQ(w.size(), 9u);
  double linear = 0, shown = 0;
  for (const float v : values) {
    linear += 3.0 * v * v;
    const double d = srgb_encode(std::min(1.0f, v));
    shown += 3.0 * d * d;
  }
  EXPECT_NEAR(w[0], 1 / linear + 12.92 * 12.92 / shown, 1e-3 * w[0]);
  EXPECT_NEAR(w[8], 1 / linear, 1e-12);
  EXPECT_GT(w[3], 5 * w[8]);  // mid grey is seen; a clamped highlight only counts linearly
  // Unmeasured pixels do not enter the sums.
  const std::vector<double> two = linear_and_shown_weights(image, {true, true, false}, ToneMap{ToneMap::Curve::clamp, 0.0});
  EXPECT_NEAR(two[8], 1 / (linear - 75.0), 1e-9);
}

TEST(AdaptiveSampling, InvalidSettingsAreRefused) {
  AdaptiveSampling s;
  s.floor = 0;
  EXPECT_THROW(s.validate(), Error);
  s = {};
  s.cap = 0.5;
  EXPECT_THROW(s.validate(), Error);
  s = {};
  s.radius = -1;
  EXPECT_THROW(s.validate(), Error);
}

TEST(AdaptiveSampling, ARenderTakesTheSharesAsItsPixelsSampleCounts) {
  SceneDescription d;
  d.constant_radiance = Rgb::Constant(1.0);
  const Scene scene(d);
  RenderSettings s;
  s.width = s.height = 8;
  s.spp = 16;
  auto shares = std::make_shared<std::vector<double>>(64, 0.5);
  (*shares)[9] = 4.0;
  (*shares)[10] = 0.01;
  s.pixel_samples = shares;
  const std::vector<int> counts = sample_counts(scene, s);
  EXPECT_EQ(counts[0], 8);
  EXPECT_EQ(counts[9], 64);
  EXPECT_EQ(counts[10], 1);  // at least one
  const FunctionMaterial grey([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.15); });
  RenderStats stats;
  render(scene, grey, s, null_progress(), &stats);
  EXPECT_EQ(stats.camera_samples, static_cast<std::uint64_t>(std::accumulate(counts.begin(), counts.end(), 0)));
  // Shares of another size, or not positive, are the caller's error.
  s.pixel_samples = std::make_shared<std::vector<double>>(63, 1.0);
  EXPECT_THROW(render(scene, grey, s), Error);
  (*shares)[3] = -1.0;
  s.pixel_samples = shares;
  EXPECT_THROW(render(scene, grey, s), Error);
}

/// A glossy conductor: under test::sky_scene() its noise sits in the sun's highlight.
std::shared_ptr<const Material> adaptive_gold() {
  return std::make_shared<FunctionMaterial>(
      [g = GgxConductor{Rgb(0.95, 0.64, 0.54), 0.05}](const Vec3& wi, const Vec3& wo) { return g(wi, wo); });
}

ProgressiveSettings adaptive_settings(std::uint64_t seed, bool adaptive) {
  ProgressiveSettings s;
  s.render.width = s.render.height = 32;
  s.render.spp = 16;
  s.render.seed = seed;
  s.limits.max_pass_spp = 64;
  s.limits.target_error = 1e-9;
  s.adaptive.enabled = adaptive;
  return s;
}

TEST(AdaptiveSampling, AnAdaptiveRefinementIsUnbiasedAndLessNoisy) {
  // The reference: uniform samples, 64x the tested refinements'.
  ProgressiveSettings rs = adaptive_settings(4242, false);
  rs.limits.max_pass_spp = 1024;
  rs.limits.max_spp = 8192;
  ProgressiveRender reference(test::sky_scene(), adaptive_gold(), rs);
  while (!reference.state().converged) reference.refine(10.0);
  const double reference_error = reference.state().relative_error;

  const auto refined = [&](bool adaptive) {
    auto r = std::make_unique<ProgressiveRender>(test::sky_scene(), adaptive_gold(), adaptive_settings(7, adaptive));
    while (r->state().spp < 128) r->refine(0.0);
    return r;
  };
  const auto uniform_ptr = refined(false), adapted_ptr = refined(true);
  const ProgressiveRender &uniform = *uniform_ptr, &adapted = *adapted_ptr;
  EXPECT_EQ(uniform.pixel_samples(), nullptr);
  ASSERT_NE(adapted.pixel_samples(), nullptr);
  const std::vector<double>& shares = *adapted.pixel_samples();
  EXPECT_NEAR(mean_of(shares), 1.0, 1e-9);
  EXPECT_GT(*std::max_element(shares.begin(), shares.end()), 8.0) << "the highlight takes many samples";

  const auto error = [&](const ProgressiveRender& r) {
    const double m = test::object_relative_rms(r.image(), reference.image(), r.object_pixels());
    return std::sqrt(std::max(0.0, m * m - reference_error * reference_error));
  };
  // Unbiased: the error against the reference is what the refinement's own estimate says (a bias
  // would add to the measured error and not to the estimate).
  EXPECT_LT(error(adapted), 1.6 * adapted.state().relative_error + 0.002);
  // Less noise at equal samples, and no more as shown (ACES: the highlight saturates).
  EXPECT_LT(adapted.state().relative_error, 0.6 * uniform.state().relative_error);
  EXPECT_LT(error(adapted), 0.7 * error(uniform));
  const auto shown_error = [&](const ProgressiveRender& r) {
    const auto shown = [](float v) { return srgb_encode(std::min(1.0f, tone_curve(v, 1.0f, ToneMap::Curve::aces))); };
    double d = 0;
    const Image a = r.image(), b = reference.image();
    for (std::size_t p = 0; p < r.object_pixels().size(); ++p)
      if (r.object_pixels()[p])
        for (std::size_t c = 0; c < 3; ++c) d += std::pow(shown(a.rgb[3 * p + c]) - shown(b.rgb[3 * p + c]), 2);
    return std::sqrt(d);
  };
  EXPECT_LT(shown_error(adapted), shown_error(uniform));
}

TEST(AdaptiveSampling, TheTrialPassRestartsTheRefinement) {
  ProgressiveRender r(test::sky_scene(), adaptive_gold(), adaptive_settings(9, true));
  r.refine(0.0);
  EXPECT_EQ(r.state().passes, 1);
  EXPECT_EQ(r.pixel_samples(), nullptr);  // the first pass is plain
  r.refine(0.0);
  // The trial's halves chose the shares and were dropped: the pass made with them is the first.
  EXPECT_EQ(r.state().passes, 1);
  ASSERT_NE(r.pixel_samples(), nullptr);
  r.refine(0.0);
  EXPECT_EQ(r.state().passes, 2);
}

/// Counts progress updates; throws at update `limit` (0: never).
struct CountingSink final : ProgressSink {
  explicit CountingSink(int at) : limit(at) {}
  void update(const std::string&, std::uint64_t, std::uint64_t) override {
    if (++count == limit) throw std::runtime_error("cancelled");
  }
  void message(const std::string&) override {}
  void finish(const std::string&) override {}
  int limit, count = 0;
};

TEST(AdaptiveSampling, ACancelledTrialLeavesEverythingAsItWas) {
  // The trial's updates, counted on a twin; then cancelled at its last update (inside the pass
  // made with the new shares) and at its first.
  ProgressiveRender twin(test::sky_scene(), adaptive_gold(), adaptive_settings(9, true));
  twin.refine(0.0);
  CountingSink counter(0);
  twin.refine(0.0, counter);
  ASSERT_GT(counter.count, 2);
  for (const int at : {counter.count, 1}) {
    ProgressiveRender r(test::sky_scene(), adaptive_gold(), adaptive_settings(9, true));
    r.refine(0.0);
    const Image before = r.image();
    CountingSink cancel(at);
    EXPECT_THROW(r.refine(0.0, cancel), std::runtime_error);
    EXPECT_EQ(r.state().passes, 1);
    EXPECT_EQ(r.image().rgb, before.rgb);
    EXPECT_EQ(r.pixel_samples(), nullptr);
    r.refine(0.0);  // the trial again, completed
    EXPECT_EQ(r.state().passes, 1);
    EXPECT_NE(r.pixel_samples(), nullptr);
  }
}

}  // namespace
}  // namespace matlas::render
