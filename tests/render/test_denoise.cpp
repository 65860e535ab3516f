// The dual-buffer non-local means denoiser (render/denoise.h): it lowers the error of noisy halves
// against the known image several times, leaves a noise-free input as it is (consistency), keeps
// a step edge, never mixes regions, its error estimate follows the variance, and on a rendered
// preview it brings 64 spp closer to a long reference than the plain mean of 4x the samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "brdf/analytic.h"
#include "core/error.h"
#include "render/denoise.h"
#include "render/progressive_render.h"
#include "render_test_util.h"

namespace matlas::render {
namespace {

/// A smooth image: a horizontal ramp times a vertical cosine, in [0.2, 1.2].
Image smooth_image(int w, int h) {
  Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        im.pixel(x, y)[c] = static_cast<float>(0.2 + 0.5 * x / w + 0.5 * (0.5 + 0.5 * std::cos(0.1 * y + c)));
  return im;
}

/// The image plus Gaussian noise of standard deviation sigma (relative to the value).
Image noisy(const Image& truth, double sigma, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Image out = truth;
  for (float& v : out.rgb) v = static_cast<float>(v * (1.0 + sigma * n(rng)));
  return out;
}

double rms_relative(const Image& a, const Image& truth) {
  double d = 0, s = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    d += (double(a.rgb[i]) - truth.rgb[i]) * (double(a.rgb[i]) - truth.rgb[i]);
    s += double(truth.rgb[i]) * truth.rgb[i];
  }
  return std::sqrt(d / s);
}

Image mean_of(const Image& a, const Image& b) {
  Image out = a;
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
  return out;
}

TEST(Denoise, LowersTheErrorOfNoisyHalvesSeveralTimes) {
  const Image truth = smooth_image(64, 48);
  const Image a = noisy(truth, 0.2, 1), b = noisy(truth, 0.2, 2);
  const double before = rms_relative(mean_of(a, b), truth);
  const DenoiseResult r = denoise_halves(a, b, 16, 16, {});
  const double after = rms_relative(r.image, truth);
  EXPECT_NEAR(before, 0.2 / std::sqrt(2.0), 0.01);
  EXPECT_LT(after, before / 4) << "before " << before << " after " << after;
  // The estimate sees the variance left, not the bias: it is below the plain mean's error and
  // of the order of the true error on a smooth image.
  EXPECT_LT(r.relative_error, before / 3);
  EXPECT_GT(r.relative_error, after / 4);
}

TEST(Denoise, ANoiseFreeInputComesBackUnchanged) {
  const Image truth = smooth_image(40, 30);
  const DenoiseResult r = denoise_halves(truth, truth, 8, 24, {});
  for (std::size_t i = 0; i < truth.rgb.size(); ++i) ASSERT_NEAR(r.image.rgb[i], truth.rgb[i], 1e-6 * truth.rgb[i]) << i;
  EXPECT_EQ(r.relative_error, 0.0);
}

TEST(Denoise, KeepsAStepEdge) {
  // Left half 1, right half 4, with 10 % noise: the filter smooths each side, not across.
  Image truth(48, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) truth.pixel(x, y)[c] = x < 24 ? 1.0f : 4.0f;
  const Image a = noisy(truth, 0.1, 3), b = noisy(truth, 0.1, 4);
  const DenoiseResult r = denoise_halves(a, b, 8, 8, {});
  double worst_edge = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 22; x < 26; ++x)
      for (int c = 0; c < 3; ++c)
        worst_edge = std::max(worst_edge, std::abs(double(r.image.pixel(x, y)[c]) - truth.pixel(x, y)[c]) / truth.pixel(x, y)[c]);
  EXPECT_LT(worst_edge, 0.25) << "the edge is blurred";
  EXPECT_LT(rms_relative(r.image, truth), rms_relative(mean_of(a, b), truth) / 2);
}

TEST(Denoise, RegionsDoNotMixAndLabelZeroIsLeftAsItIs) {
  // Two regions of equal value: a noise-free one must stay exactly as it is although its
  // neighbours in the other (noisy) region look alike; label 0 pixels are not filtered at all.
  Image a(32, 16), b(32, 16);
  std::vector<std::uint8_t> region(32 * 16);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.5f, 1.5f);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 32 + x;
      region[p] = x < 12 ? 1 : x < 14 ? 0 : 2;
      for (int c = 0; c < 3; ++c) {
        a.pixel(x, y)[c] = x < 12 ? 1.0f : u(rng);
        b.pixel(x, y)[c] = x < 12 ? 1.0f : u(rng);
      }
    }
  const DenoiseResult r = denoise_halves(a, b, 4, 4, region);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 14; ++x)
      for (int c = 0; c < 3; ++c) {
        const float expected = 0.5f * (a.pixel(x, y)[c] + b.pixel(x, y)[c]);
        ASSERT_FLOAT_EQ(r.image.pixel(x, y)[c], expected) << x << "," << y;
      }
}

TEST(Denoise, TheErrorEstimateFallsWithTheNoise) {
  const Image truth = smooth_image(48, 48);
  const DenoiseResult loud = denoise_halves(noisy(truth, 0.2, 6), noisy(truth, 0.2, 7), 16, 16, {});
  const DenoiseResult quiet = denoise_halves(noisy(truth, 0.05, 8), noisy(truth, 0.05, 9), 256, 256, {});
  EXPECT_LT(quiet.relative_error, loud.relative_error);
  EXPECT_LT(rms_relative(quiet.image, truth), rms_relative(loud.image, truth));
}

TEST(Denoise, BadInputIsRefused) {
  const Image a(8, 8), b(8, 6);
  EXPECT_THROW(denoise_halves(a, b, 1, 1, {}), Error);
  EXPECT_THROW(denoise_halves(a, a, 0, 1, {}), Error);
  EXPECT_THROW(denoise_halves(a, a, 1, 1, std::vector<std::uint8_t>(7, 1)), Error);
  DenoiseSettings s;
  s.strength = 0;
  EXPECT_THROW(denoise_halves(a, a, 1, 1, {}, {}, s), Error);
  s = {};
  s.search_radius = 33;
  EXPECT_THROW(s.validate(), Error);
}

TEST(Denoise, ARenderedPreviewAt64SppIsCloserToTheReferenceThanThePlainMean) {
  // A glossy conductor under a sky (the synthetic map without its sun), 48 x 48: the denoised
  // 64-spp image against a 4096-spp reference is closer than the plain 64-spp mean, and not
  // worse than that of 128 spp.
  Image sky = test::synthetic_environment();
  for (int y = 3; y <= 4; ++y)
    for (int x = 20; x <= 21; ++x) std::copy(sky.pixel(x, 6), sky.pixel(x, 6) + 3, sky.pixel(x, y));
  const auto scene = std::make_shared<const Scene>(SceneDescription{}, std::nullopt, Environment(sky));
  const auto gold = std::make_shared<FunctionMaterial>(
      [g = GgxConductor{Rgb(0.95, 0.64, 0.54), 0.2}](const Vec3& wi, const Vec3& wo) { return g(wi, wo); });
  const auto settings = [](int spp, std::uint64_t seed, int max_spp) {
    ProgressiveSettings s;
    s.render.width = s.render.height = 48;
    s.render.spp = spp;
    s.render.seed = seed;
    s.limits.max_pass_spp = spp;
    s.limits.max_spp = max_spp;
    s.limits.target_error = 1e-9;
    s.adaptive.enabled = false;  // the plain mean of two uniform passes, as the denoiser's input
    return s;
  };
  ProgressiveRender reference(scene, gold, settings(256, 99, 4096));
  while (!reference.state().converged) reference.refine(100.0);
  ProgressiveRender r(scene, gold, settings(32, 1, 1 << 20));
  r.refine(0.0);
  r.refine(0.0);
  ASSERT_EQ(r.state().spp, 64);
  const DenoiseResult d = r.denoised();
  const Image truth = reference.image();
  const auto error = [&](const Image& im) {
    double s2 = 0, sig = 0;
    for (std::size_t p = 0; p < r.object_pixels().size(); ++p) {
      if (!r.object_pixels()[p]) continue;
      for (int c = 0; c < 3; ++c) {
        const double x = im.rgb[3 * p + c], y = truth.rgb[3 * p + c];
        s2 += (x - y) * (x - y);
        sig += y * y;
      }
    }
    return std::sqrt(s2 / sig);
  };
  const double plain64 = error(r.image()), denoised64 = error(d.image);
  while (r.state().spp < 128) r.refine(0.0);
  const double plain128 = error(r.image());
  EXPECT_LT(denoised64, 0.75 * plain64) << "plain 64: " << plain64 << ", denoised 64: " << denoised64 << ", plain 128: " << plain128;
  EXPECT_LE(denoised64, plain128);
}

}  // namespace
}  // namespace matlas::render
