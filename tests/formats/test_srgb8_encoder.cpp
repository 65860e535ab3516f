// Srgb8Encoder: the same 8-bit codes as tone_map_to_srgb8 (the per-value reference with pow()),
// for every tone curve, several exposures and the edge values. (All 1.07e9 floats in [0, 2] were
// compared once for the clamp curve at exposure 0: no difference; this test samples them.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "formats/image_io.h"
#include "formats/srgb8_encoder.h"

namespace matlas {
namespace {

TEST(Srgb8Encoder, MatchesTheReferenceOnEveryStepAndASampleOfAllFloats) {
  const Srgb8Encoder encoder({});
  int steps = 0;
  // Every 97th float bit pattern from 0 to 2 (about 11 M values), and both sides of each step.
  for (std::uint32_t b = 0; b <= 0x40000000u; b += 97) {
    const float x = std::bit_cast<float>(b);
    ASSERT_EQ(encoder(x), tone_map_to_srgb8(x, {})) << "x = " << x;
  }
  // Wherever the code changes between two patterns 64 apart, every value in between.
  unsigned char previous = tone_map_to_srgb8(0.0f, {});
  for (std::uint32_t b = 64; b <= 0x3F800000u; b += 64) {
    const unsigned char code = tone_map_to_srgb8(std::bit_cast<float>(b), {});
    if (code == previous) continue;
    previous = code;
    ++steps;
    for (std::uint32_t d = b - 64; d <= b; ++d) {
      const float y = std::bit_cast<float>(d);
      ASSERT_EQ(encoder(y), tone_map_to_srgb8(y, {})) << "y = " << y;
    }
  }
  EXPECT_EQ(steps, 255);  // each step of the code lies between two of the patterns
}

TEST(Srgb8Encoder, MatchesTheReferenceForEveryCurveAndExposure) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> log_value(-12.0f, 6.0f);
  for (const auto curve : {ToneMap::Curve::clamp, ToneMap::Curve::reinhard, ToneMap::Curve::aces})
    for (const double exposure : {-3.0, -0.5, 0.0, 1.0, 2.7}) {
      const ToneMap tone{curve, exposure};
      const Srgb8Encoder encoder(tone);
      std::vector<float> in;
      for (int i = 0; i < 200000; ++i) in.push_back(std::exp2(log_value(rng)));
      for (const float edge : {0.0f, -0.0f, -1.0f, 1.0f, 1e-30f, 1e30f, std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                               std::numeric_limits<float>::denorm_min()})
        in.push_back(edge);
      std::vector<unsigned char> out(in.size());
      encoder.encode(in.data(), out.data(), in.size());
      for (std::size_t i = 0; i < in.size(); ++i)
        ASSERT_EQ(out[i], tone_map_to_srgb8(in[i], tone)) << "x = " << in[i] << ", exposure " << exposure;
    }
}

}  // namespace
}  // namespace matlas
