#include "formats/srgb8_encoder.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/error.h"

namespace matlas {

namespace {

/// Bits of a float in [0, 1] shifted right by this many index the table: 2^8 buckets per octave,
/// 32,513 entries up to 1.0f.
constexpr int kShift = 15;

/// thresholds[k]: the smallest non-negative float whose code is at least k (k = 1..255), and the
/// table of codes at the start of each bucket. Built once; the code is non-decreasing in x.
struct Steps {
  std::array<float, 257> thresholds{};
  std::vector<unsigned char> bucket_code;

  Steps() {
    constexpr std::uint32_t one = 0x3F800000u;  // 1.0f
    thresholds[0] = 0.0f;
    for (int k = 1; k <= 255; ++k) {
      // Bisection on the bit patterns of [0, 1] (ordered as the values).
      std::uint32_t lo = 0, hi = one;  // code(lo) < k <= code(hi)
      while (hi - lo > 1) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (srgb8_code(std::bit_cast<float>(mid)) >= k) hi = mid;
        else lo = mid;
      }
      thresholds[static_cast<std::size_t>(k)] = std::bit_cast<float>(hi);
    }
    thresholds[256] = INFINITY;
    bucket_code.resize((one >> kShift) + 1);
    for (std::size_t b = 0; b < bucket_code.size(); ++b)
      bucket_code[b] = srgb8_code(std::bit_cast<float>(static_cast<std::uint32_t>(b << kShift)));
    // No bucket holds two steps (the steepest part, near 1, has 67 steps per octave of 256
    // buckets), so one comparison after the table finds the code.
    for (std::size_t b = 0; b + 1 < bucket_code.size(); ++b)
      if (bucket_code[b + 1] - bucket_code[b] > 1) throw Error("srgb8: two steps of the sRGB code in one bucket");
  }
};

const Steps& steps() {
  static const Steps s;
  return s;
}

}  // namespace

Srgb8Encoder::Srgb8Encoder(const ToneMap& tone)
    : scale_(static_cast<float>(std::exp2(tone.exposure))), curve_(tone.curve) {
  steps();
}

unsigned char Srgb8Encoder::code(float x) const {
  if (!(x > 0.0f)) return 0;    // also -0 (from a -0 input)
  if (!(x < 1.0f)) return 255;  // also +inf from a huge exposure
  const Steps& s = steps();
  const unsigned k = s.bucket_code[std::bit_cast<std::uint32_t>(x) >> kShift];
  return static_cast<unsigned char>(k + (x >= s.thresholds[k + 1] ? 1u : 0u));
}

unsigned char Srgb8Encoder::operator()(float linear) const { return code(tone_curve(linear, scale_, curve_)); }

void Srgb8Encoder::encode(const float* in, unsigned char* out, std::size_t count) const {
  if (curve_ != ToneMap::Curve::clamp) {
    for (std::size_t i = 0; i < count; ++i) out[i] = (*this)(in[i]);
    return;
  }
  // The clamp curve (the previews'): tone_curve's first two steps inline, the same arithmetic.
  for (std::size_t i = 0; i < count; ++i) out[i] = code((std::isfinite(in[i]) ? std::max(in[i], 0.0f) : 0.0f) * scale_);
}

}  // namespace matlas
