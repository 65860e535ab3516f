// The stratified sampler (render/pixel_sampler.h): Sobol points stratified after scrambling, the
// split of a pixel's samples among the strategies, and random numbers that do not depend on the
// material (what keeps the images linear in the BRDF table).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <set>

#include "brdf/analytic.h"
#include "core/error.h"
#include "render/material.h"
#include "render/pixel_sampler.h"
#include "render/render.h"
#include "render/scene.h"
#include "render_test_util.h"

namespace matlas::render {
namespace {

TEST(PixelSampler, SobolSecondDimensionIsTheKnownSequence) {
  const double expected[] = {0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (std::uint32_t i = 0; i < 8; ++i) {
    std::uint32_t x[4];
    sobol_4d(i, x);
    EXPECT_EQ(x[1] / 4294967296.0, expected[i]) << "index " << i;
  }
}

TEST(PixelSampler, TableDrivenSobolEqualsTheGeneratorMatrixProduct) {
  // Scrambled indices are arbitrary 32-bit words: every byte position and the top bit matter.
  std::vector<std::uint32_t> indices = {0u, 1u, 255u, 256u, 0x80000000u, 0xFFFFFFFFu, 0x01020304u};
  std::uint64_t z = 12345;
  for (int i = 0; i < 2000; ++i) {
    z = z * 6364136223846793005ull + 1442695040888963407ull;
    indices.push_back(static_cast<std::uint32_t>(z >> 32));
  }
  for (const std::uint32_t index : indices) {
    std::uint32_t x[4];
    sobol_4d(index, x);
    for (int d = 0; d < 4; ++d) ASSERT_EQ(x[d], sobol_dimension(d, index)) << "index " << index << " dimension " << d;
  }
}

TEST(PixelSampler, ScrambledPointsAreStratifiedInEveryDimensionAndTheJitterIsANet) {
  for (const std::uint64_t pixel : {0ull, 17ull, 123457ull})
    for (const int strategy : {0, 3}) {
      const PixelSampler sampler(5, pixel);
      constexpr int kCount = 64;  // 2^6
      std::array<std::set<int>, 4> cells;
      std::vector<std::array<double, 4>> points(kCount);
      for (int j = 0; j < kCount; ++j) {
        sampler.point(strategy, j, points[static_cast<std::size_t>(j)].data());
        for (std::size_t d = 0; d < 4; ++d) {
          const double u = points[static_cast<std::size_t>(j)][d];
          ASSERT_GE(u, 0.0);
          ASSERT_LT(u, 1.0);
          cells[d].insert(static_cast<int>(u * kCount));
        }
      }
      for (std::size_t d = 0; d < 4; ++d) EXPECT_EQ(cells[d].size(), std::size_t{kCount}) << "dimension " << d;
      // The jitter: one point in every elementary box of 64 cells, all shapes 2^a x 2^(6-a).
      for (int a = 0; a <= 6; ++a) {
        std::set<int> boxes;
        for (const auto& p : points)
          boxes.insert(static_cast<int>(p[0] * (1 << a)) * 64 + static_cast<int>(p[1] * (1 << (6 - a))));
        EXPECT_EQ(boxes.size(), std::size_t{kCount}) << "boxes 2^" << a << " x 2^" << 6 - a;
      }
    }
}

TEST(PixelSampler, PixelsAndStrategiesGetDifferentPoints) {
  double a[4], b[4], c[4];
  PixelSampler(1, 10).point(0, 0, a);
  PixelSampler(1, 11).point(0, 0, b);
  PixelSampler(1, 10).point(1, 0, c);
  EXPECT_NE(a[0], b[0]);
  EXPECT_NE(a[0], c[0]);
  PixelSampler(2, 10).point(0, 0, b);
  EXPECT_NE(a[2], b[2]);
}

TEST(PixelSampler, PlanSplitsTheSamplesInProportion) {
  SamplingMixture m(0.5, 0.05, {{0.005, 0.2}, {0.02, 0.1}, {0.3, 0.0}});
  m.set_profile({1.0, 2.0, 3.0}, 0.15);
  for (const int spp : {1, 7, 32, 64, 100}) {
    const StrategyPlan plan = plan_strategies(m, spp);
    ASSERT_EQ(plan.counts.size(), 6u);  // environment, cosine, three lobes, tabulated
    int sum = 0;
    const double p[] = {0.5, 0.05, 0.2, 0.1, 0.0, 0.15};
    for (std::size_t k = 0; k < 6; ++k) {
      sum += plan.counts[k];
      EXPECT_LT(std::abs(plan.counts[k] - p[k] * spp), 1.0) << "strategy " << k << ", spp " << spp;
    }
    EXPECT_EQ(sum, spp);
    EXPECT_EQ(plan.counts[4], 0);  // probability 0: never drawn
    // The density is the mixture with the counts as probabilities.
    EXPECT_EQ(plan.density.environment, plan.counts[0]);
    EXPECT_EQ(plan.density.tabulated, plan.counts[5]);
  }
  const StrategyPlan plan = plan_strategies(m, 64);
  EXPECT_EQ(plan.counts, (std::vector<int>{32, 3, 13, 6, 0, 10}));
  EXPECT_THROW(plan_strategies(m, 0), Error);
}

/// Records every direction pair it is evaluated at (a canonical order: sorted).
class RecordingMaterial final : public Material {
public:
  explicit RecordingMaterial(BrdfFunction f) : f_(std::move(f)) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override {
    std::lock_guard lock(mutex_);
    taps_.push_back({wi.x(), wi.y(), wi.z(), wo.x(), wo.y(), wo.z()});
    return f_(wi, wo);
  }
  std::vector<std::array<double, 6>> sorted() const {
    std::vector<std::array<double, 6>> t = taps_;
    std::sort(t.begin(), t.end());
    return t;
  }

private:
  BrdfFunction f_;
  mutable std::mutex mutex_;
  mutable std::vector<std::array<double, 6>> taps_;
};

RenderSettings small_settings(Sampler sampler, bool power) {
  RenderSettings s;
  s.width = s.height = 20;
  s.spp = 16;
  s.mixture = SamplingMixture(0.5, 0.05, {{0.005, 0.2}, {0.1, 0.1}});
  s.mixture.set_profile({5.0, 1.0, 0.5, 0.1}, 0.15);
  s.sampler = sampler;
  s.power_heuristic = power;
  return s;
}

void expect_material_independent_samples(const RenderSettings& s) {
  const Scene scene(SceneDescription{}, std::nullopt, Environment(test::synthetic_environment()));
  const GgxConductor chrome{Rgb(0.95, 0.93, 0.9), 0.004};
  const Lambertian matte{Rgb(0.2, 0.5, 0.8)};
  RecordingMaterial a([&](const Vec3& wi, const Vec3& wo) { return chrome(wi, wo); });
  RecordingMaterial b([&](const Vec3& wi, const Vec3& wo) { return matte(wi, wo); });
  const Image image_a = render(scene, a, s), image_b = render(scene, b, s);
  const auto taps_a = a.sorted(), taps_b = b.sorted();
  EXPECT_GT(taps_a.size(), 1000u);
  EXPECT_EQ(taps_a, taps_b);  // exactly the same directions, whatever the BRDF
  // And the weights: the image of a + b is the sum of the images (same samples, linear).
  const FunctionMaterial sum([&](const Vec3& wi, const Vec3& wo) -> Rgb { return chrome(wi, wo) + matte(wi, wo); });
  const Image iab = render(scene, sum, s);
  const std::vector<float> coverage = object_coverage(scene, s);
  for (std::size_t p = 0; p < coverage.size(); ++p) {
    if (coverage[p] != 1.0f) continue;
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(iab.rgb[3 * p + c], image_a.rgb[3 * p + c] + image_b.rgb[3 * p + c], 1e-5 * (1.0 + iab.rgb[3 * p + c]));
  }
}

TEST(PixelSampler, TheSamplesDoNotDependOnTheMaterial) {
  ASSERT_EQ(RenderSettings{}.sampler, Sampler::light_and_lobe);  // the default
  expect_material_independent_samples(small_settings(Sampler::light_and_lobe, false));
  expect_material_independent_samples(small_settings(Sampler::stratified, false));
}

TEST(PixelSampler, ThePowerHeuristicSamplesDoNotDependOnTheMaterial) {
  expect_material_independent_samples(small_settings(Sampler::light_and_lobe, true));
  expect_material_independent_samples(small_settings(Sampler::stratified, true));
}

TEST(PixelSampler, LightAndLobeRefusesAMixtureWithoutLobes) {
  RenderSettings s = small_settings(Sampler::light_and_lobe, false);
  s.mixture = SamplingMixture(1.0, 0.0, {});
  EXPECT_THROW(
      {
        try {
          s.validate();
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("lobe strategy"), std::string::npos) << e.what();
          throw;
        }
      },
      Error);
  s.sampler = Sampler::stratified;  // the environment alone is a valid stratified mixture
  EXPECT_NO_THROW(s.validate());
}

/// A furnace (uniform radiance 1) with a white Lambertian, and the synthetic sky with a glossy
/// conductor: the unbiasedness checks of the samplers.
struct UnbiasednessScenes {
  static SceneDescription furnace_description() {
    SceneDescription d;
    d.constant_radiance = Rgb::Constant(1.0);
    return d;
  }
  Scene furnace{furnace_description()};
  Scene sky{SceneDescription{}, std::nullopt, Environment(test::synthetic_environment())};
  FunctionMaterial white{[](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(1.0 / kPi); }};
  FunctionMaterial gold{[g = GgxConductor{Rgb(0.95, 0.64, 0.54), 0.15}](const Vec3& wi, const Vec3& wo) {
    return g(wi, wo);
  }};

  /// Furnace: a white Lambertian in a uniform environment of radiance 1 reflects exactly 1; the
  /// MIS weights vary over the directions (the lobes' density does), so wrong weights show. The
  /// glossy conductor under the sky with its small bright sun: the same mean as `reference`
  /// (itself tested against closed forms elsewhere).
  void expect_unbiased(const RenderSettings& reference, const RenderSettings& s) const {
    const std::vector<float> coverage = object_coverage(furnace, reference);
    const Image sky_reference = render(sky, gold, reference);
    const Image image = render(furnace, white, s), glossy_image = render(sky, gold, s);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(test::covered_mean(image, coverage, c), 1.0, 0.01);
      const double expected = test::covered_mean(sky_reference, coverage, c);
      EXPECT_NEAR(test::covered_mean(glossy_image, coverage, c), expected, 0.02 * expected);
    }
  }
};

TEST(PixelSampler, LightAndLobeAndThePowerHeuristicAreUnbiased) {
  RenderSettings reference = small_settings(Sampler::stratified, false);
  reference.width = reference.height = 24;
  reference.spp = 256;
  reference.grazing_samples = 1.0;
  const UnbiasednessScenes t;
  for (const auto& [sampler, power] : {std::pair{Sampler::light_and_lobe, false}, std::pair{Sampler::light_and_lobe, true},
                                       std::pair{Sampler::stratified, true}}) {
    RenderSettings s = reference;
    s.sampler = sampler;
    s.power_heuristic = power;
    t.expect_unbiased(reference, s);
  }
}

TEST(GrazingSamples, CountsFollowTheViewAngleAndKeepTheMeanSpp) {
  const Scene scene(SceneDescription{}, std::nullopt, Environment(test::synthetic_environment()));
  RenderSettings s;
  s.width = s.height = 64;
  s.spp = 32;
  s.grazing_samples = 4.0;
  const std::vector<int> counts = sample_counts(scene, s);
  ASSERT_EQ(counts.size(), 64u * 64u);
  double total = 0;
  for (const int n : counts) total += n;
  EXPECT_NEAR(total / static_cast<double>(counts.size()), 32.0, 0.5);  // the same samples in all (rounding)
  // The sphere's centre and the background take the frontal count; the rim up to 4x that.
  const int centre = counts[32 * 64 + 32], corner = counts[0];
  const int most = *std::max_element(counts.begin(), counts.end()), least = *std::min_element(counts.begin(), counts.end());
  EXPECT_EQ(centre, corner);
  EXPECT_EQ(least, centre);
  EXPECT_GE(most, 3 * centre);
  EXPECT_LE(most, 4 * centre + 2);  // both rounded
  // Along the row through the centre, the counts grow from the centre to the rim.
  const std::vector<float> coverage = object_coverage(scene, s);
  int previous = centre;
  for (int x = 33; x < 64 && coverage[32 * 64 + static_cast<std::size_t>(x)] == 1.0f; ++x) {
    EXPECT_GE(counts[32 * 64 + static_cast<std::size_t>(x)], previous) << "x " << x;
    previous = counts[32 * 64 + static_cast<std::size_t>(x)];
  }
  EXPECT_GT(previous, centre);
  // Off: spp everywhere.
  s.grazing_samples = 1.0;
  for (const int n : sample_counts(scene, s)) ASSERT_EQ(n, 32);
  s.grazing_samples = 0.5;
  EXPECT_THROW(s.validate(), Error);
}

TEST(GrazingSamples, TheSamplesDoNotDependOnTheMaterialAndStayUnbiased) {
  for (const Sampler sampler : {Sampler::light_and_lobe, Sampler::stratified, Sampler::independent}) {
    RenderSettings s = small_settings(sampler, false);
    s.grazing_samples = 4.0;
    expect_material_independent_samples(s);
  }
  // Furnace and the glossy conductor under the sky, as for the samplers above.
  RenderSettings uniform = small_settings(Sampler::light_and_lobe, false);
  uniform.width = uniform.height = 24;
  uniform.spp = 256;
  uniform.grazing_samples = 1.0;
  RenderSettings grazing = uniform;
  grazing.grazing_samples = 4.0;
  const UnbiasednessScenes t;
  t.expect_unbiased(uniform, grazing);
  RenderStats stats;
  (void)render(t.furnace, t.white, grazing, null_progress(), &stats);
  EXPECT_NEAR(static_cast<double>(stats.camera_samples) / (24.0 * 24.0 * 256.0), 1.0, 0.01);
}

}  // namespace
}  // namespace matlas::render
