// Refinement, the one bookkeeping of refined images, with synthetic passes of known noise: the
// mean is the samples-weighted mean of the passes, the error estimate matches the noise the passes
// were drawn with, unmeasured pixels do not count, pass k gets seed k, limits stop it, and a
// cancelled pass leaves the state as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "render/refinement.h"

namespace matlas::render {
namespace {

constexpr int kSide = 32;

/// A pass of `spp` samples of an image whose pixels are `level` (red), 2 level (green), 3 level
/// (blue) with per-sample noise `sigma` in every channel: per pixel the mean of spp samples, i.e.
/// Gaussian noise of standard deviation sigma / sqrt(spp). Pixels with `wild` set get noise 10x.
Refinement::Pass noisy_pass(double level, double sigma, std::vector<int>* seeds = nullptr,
                            std::vector<bool> wild = {}) {
  return [=](int spp, std::uint64_t seed, ProgressSink&) {
    if (seeds) seeds->push_back(static_cast<int>(seed));
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    Image out(kSide, kSide);
    for (std::size_t p = 0; p < out.rgb.size() / 3; ++p)
      for (std::size_t c = 0; c < 3; ++c) {
        const double s = sigma * (!wild.empty() && wild[p] ? 10.0 : 1.0) / std::sqrt(static_cast<double>(spp));
        out.rgb[p * 3 + c] = static_cast<float>(level * static_cast<double>(c + 1) + s * normal(rng));
      }
    return out;
  };
}

Refinement::PassSeed plain_seed() {
  return [](int pass) { return static_cast<std::uint64_t>(1000 + pass); };
}

RefinementLimits never_converging(int max_pass_spp = 8) {
  return {.target_error = 1e-12, .min_converged_spp = 1, .max_spp = 1 << 20, .max_pass_spp = max_pass_spp};
}

/// RMS of the exact image (level, 2 level, 3 level) relative to which the error is reported.
double exact_rms(double level) { return level * std::sqrt((1.0 + 4.0 + 9.0) / 3.0); }

TEST(Refinement, TheErrorEstimateMatchesTheNoiseOfThePasses) {
  const double level = 0.5, sigma = 0.8;
  std::vector<int> seeds;
  Refinement r(kSide, kSide, {}, 4, never_converging(), noisy_pass(level, sigma, &seeds), plain_seed(), "test");
  EXPECT_FALSE(std::isfinite(r.state().relative_error));
  RefinementState st;
  for (int i = 0; i < 12; ++i) st = r.refine(0.0);
  ASSERT_GE(st.passes, 12);
  // Exact: the mean of spp samples has per-value noise sigma / sqrt(spp).
  const double expected = sigma / std::sqrt(static_cast<double>(st.spp)) / exact_rms(level);
  EXPECT_NEAR(st.relative_error / expected, 1.0, 0.15) << st.relative_error << " vs " << expected;
  // The mean is the samples-weighted mean: its actual error agrees with the same figure.
  const Image mean = r.image();
  double squares = 0;
  for (std::size_t i = 0; i < mean.rgb.size(); ++i) {
    const double d = mean.rgb[i] - level * static_cast<double>(i % 3 + 1);
    squares += d * d;
  }
  const double actual = std::sqrt(squares / static_cast<double>(mean.rgb.size())) / exact_rms(level);
  EXPECT_NEAR(actual / expected, 1.0, 0.1);
  // Pass k took seed k, in order.
  ASSERT_EQ(seeds.size(), static_cast<std::size_t>(st.passes));
  for (std::size_t k = 0; k < seeds.size(); ++k) EXPECT_EQ(seeds[k], 1000 + static_cast<int>(k));
  // Both halves carry samples, and together they are the mean.
  const RefinementHalves h = r.halves();
  EXPECT_EQ(h.samples_a + h.samples_b, st.spp);
  for (std::size_t i = 0; i < mean.rgb.size(); i += 97)
    EXPECT_NEAR((h.a.rgb[i] * h.samples_a + h.b.rgb[i] * h.samples_b) / st.spp, mean.rgb[i], 1e-5);
}

TEST(Refinement, ARestartDropsThePassesAndKeepsTakingNewSeeds) {
  std::vector<int> seeds;
  Refinement r(kSide, kSide, {}, 4, never_converging(), noisy_pass(0.5, 0.8, &seeds), plain_seed(), "test");
  for (int i = 0; i < 3; ++i) r.refine(0.0);
  ASSERT_GE(r.state().passes, 3);
  r.restart();
  EXPECT_EQ(r.state().passes, 0);
  EXPECT_EQ(r.state().spp, 0);
  EXPECT_FALSE(std::isfinite(r.state().relative_error));
  EXPECT_EQ(r.halves().samples_a, 0);
  const std::size_t before = seeds.size();
  r.refine(0.0);
  EXPECT_EQ(r.state().passes, 1);
  ASSERT_EQ(seeds.size(), before + 1);
  EXPECT_EQ(seeds.back(), 1000 + static_cast<int>(before));  // a new seed, not pass 0's again
}

TEST(Refinement, UnmeasuredPixelsDoNotCount) {
  std::vector<bool> measured(kSide * kSide, true), wild(kSide * kSide, false);
  for (int p = 0; p < kSide * kSide; p += 2) measured[p] = false, wild[p] = true;
  Refinement calm(kSide, kSide, measured, 4, never_converging(), noisy_pass(0.5, 0.8, nullptr, wild), plain_seed(),
                  "test");
  Refinement all(kSide, kSide, {}, 4, never_converging(), noisy_pass(0.5, 0.8, nullptr, wild), plain_seed(), "test");
  for (int i = 0; i < 8; ++i) calm.refine(0.0), all.refine(0.0);
  const double expected = 0.8 / std::sqrt(static_cast<double>(calm.state().spp)) / exact_rms(0.5);
  EXPECT_NEAR(calm.state().relative_error / expected, 1.0, 0.2);
  EXPECT_GT(all.state().relative_error, 3 * expected);  // the wild pixels dominate when measured (about 5x)
}

TEST(Refinement, ConvergesAtTheTargetOrAtMaxSpp) {
  // A noise-free pass: the estimate is 0 as soon as both halves exist, but min_converged_spp holds.
  Refinement exact(kSide, kSide, {}, 4, {.target_error = 0.01, .min_converged_spp = 32, .max_spp = 4096, .max_pass_spp = 4},
                   noisy_pass(0.5, 0.0), plain_seed(), "test");
  RefinementState st = exact.refine(0.0);
  for (int i = 0; i < 20 && !st.converged; ++i) {
    EXPECT_LT(st.spp, 32);
    st = exact.refine(0.0);
  }
  EXPECT_TRUE(st.converged);
  EXPECT_EQ(st.spp, 32);
  EXPECT_EQ(exact.refine(10.0).passes, st.passes);  // nothing more once converged
  // Noisy passes that never reach the target stop at max_spp.
  Refinement capped(kSide, kSide, {}, 4, {.target_error = 1e-9, .min_converged_spp = 1, .max_spp = 24, .max_pass_spp = 4},
                    noisy_pass(0.5, 0.8), plain_seed(), "test");
  for (int i = 0; i < 20; ++i) capped.refine(0.0);
  EXPECT_TRUE(capped.state().converged);
  EXPECT_EQ(capped.state().spp, 24);
}

TEST(Refinement, ACancelledPassLeavesTheStateAsItWas) {
  bool cancel = false;
  const Refinement::Pass inner = noisy_pass(0.5, 0.8);
  Refinement r(
      kSide, kSide, {}, 4, never_converging(),
      [&](int spp, std::uint64_t seed, ProgressSink& progress) {
        if (cancel) throw std::runtime_error("cancelled");
        return inner(spp, seed, progress);
      },
      plain_seed(), "test");
  r.refine(0.0);
  r.refine(0.0);
  const RefinementState before = r.state();
  const Image image = r.image();
  cancel = true;
  EXPECT_THROW(r.refine(1.0), std::runtime_error);
  EXPECT_EQ(r.state().spp, before.spp);
  EXPECT_EQ(r.state().passes, before.passes);
  EXPECT_EQ(r.state().relative_error, before.relative_error);
  EXPECT_EQ(r.image().rgb, image.rgb);
}

TEST(Refinement, InvalidLimitsNameTheirOwner) {
  const auto make = [](RefinementLimits limits) {
    Refinement r(kSide, kSide, {}, 8, limits, noisy_pass(0.5, 0.1), plain_seed(), "the owner");
  };
  for (const RefinementLimits bad : {RefinementLimits{.target_error = 0}, RefinementLimits{.target_error = NAN},
                                     RefinementLimits{.min_converged_spp = 0}, RefinementLimits{.max_pass_spp = 0},
                                     RefinementLimits{.max_spp = 4}}) {
    try {
      make(bad);
      ADD_FAILURE() << "accepted invalid limits";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the owner"), std::string::npos) << e.what();
    }
  }
}

TEST(Refinement, PassesArePowersOfTwoThatGrowWithTime) {
  // next_pass_spp: the first pass's samples first; then at most doubling what is in, at most the
  // pass limit and what max_spp leaves; 0 when a later pass does not fit the time.
  EXPECT_EQ(next_pass_spp(4, 64, 4096, 0, 0.0, 0.0, true), 4);
  EXPECT_EQ(next_pass_spp(4, 64, 4096, 4, 0.004, 10.0, false), 4);   // at most doubling what is in
  EXPECT_EQ(next_pass_spp(4, 64, 4096, 512, 0.512, 10.0, false), 64);  // at most max_pass_spp
  EXPECT_EQ(next_pass_spp(4, 64, 4096, 512, 0.512, 0.02, false), 16);  // what fits 20 ms at 1 ms per sample
  EXPECT_EQ(next_pass_spp(4, 64, 520, 512, 0.512, 10.0, false), 8);   // what max_spp leaves
  EXPECT_EQ(next_pass_spp(4, 64, 4096, 512, 0.512, 0.001, false), 0);  // no time for another pass
  EXPECT_EQ(next_pass_spp(4, 64, 4096, 512, 0.512, 0.001, true), 4);   // a call's first pass always runs
}

}  // namespace
}  // namespace matlas::render
