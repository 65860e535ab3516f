#include "formats/srgb8_encoder.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>
#include <cmath>

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

unsigned char Srgb8Encoder::operator()(float linear) const {
  const float x = tone_curve(linear, scale_, curve_);
  if (!(x > 0.0f)) return 0;    // also -0 (from a -0 input)
  if (!(x < 1.0f)) return 255;  // also +inf from a huge exposure
  const Steps& s = steps();
  unsigned k = s.bucket_code[std::bit_cast<std::uint32_t>(x) >> kShift];
  while (x >= s.thresholds[k + 1]) ++k;
  return static_cast<unsigned char>(k);
}

void Srgb8Encoder::encode(const float* in, unsigned char* out, std::size_t count) const {
  for (std::size_t i = 0; i < count; ++i) out[i] = (*this)(in[i]);
}

}  // namespace matlas
