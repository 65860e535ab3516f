#pragma once
// Helpers shared by the render tests: small synthetic environment maps and scenes.
#include <cmath>

#include "formats/image_io.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas::test {

/// A 32 x 16 lat-long map: a sky gradient plus a bright warm "sun" patch.
inline Image synthetic_environment() {
  Image map(32, 16);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      float* p = map.pixel(x, y);
      const float t = 1.0f - static_cast<float>(y) / static_cast<float>(map.height);
      p[0] = 0.2f + 0.3f * t;
      p[1] = 0.25f + 0.4f * t;
      p[2] = 0.3f + 0.6f * t;
      if (y >= 3 && y <= 4 && x >= 20 && x <= 21) p[0] = 30.0f, p[1] = 25.0f, p[2] = 20.0f;
    }
  return map;
}

/// Mean of channel c over the pixels fully covered by the object.
inline double covered_mean(const Image& image, const std::vector<float>& coverage, int c) {
  double sum = 0;
  int count = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f) {
      sum += image.rgb[3 * p + static_cast<std::size_t>(c)];
      ++count;
    }
  return count ? sum / count : 0.0;
}

}  // namespace matlas::test
