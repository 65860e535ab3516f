#pragma once
// Srgb8Encoder: tone_map_to_srgb8 for many values with one tone map, without a pow() per value.
// The 8-bit code of the sRGB curve is a step function of the tone-mapped value; its 255 steps are
// found once (by bisection over the float values, with tone_map_to_srgb8's own arithmetic), and
// each value is then placed by a table indexed by its leading float bits plus one comparison.
// The codes are exactly those of tone_map_to_srgb8 (tests/formats compare them).
#include <cstddef>

#include "formats/image_io.h"

namespace matlas {

class Srgb8Encoder {
public:
  explicit Srgb8Encoder(const ToneMap& tone);

  /// The same code as tone_map_to_srgb8(linear, tone).
  unsigned char operator()(float linear) const;
  /// out[i] = (*this)(in[i]).
  void encode(const float* in, unsigned char* out, std::size_t count) const;

private:
  unsigned char code(float x) const;  ///< of a value after the tone curve

  float scale_;
  ToneMap::Curve curve_;
};

}  // namespace matlas
