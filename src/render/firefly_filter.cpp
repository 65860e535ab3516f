#include "render/firefly_filter.h"

#include <algorithm>
#include <array>
#include <string>

#include "core/error.h"

namespace matlas::render {

namespace {

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

}  // namespace

int remove_fireflies(Image& image, double ratio, int rank) {
  if (!(ratio >= 1.0)) throw Error("firefly filter: the ratio must be at least 1, got " + std::to_string(ratio));
  if (rank < 1 || rank > 2) throw Error("firefly filter: the rank must be 1 or 2, got " + std::to_string(rank));
  const Image source = image;  // neighbours are read from the unfiltered image
  int replaced = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      std::array<const float*, 8> around{};
      int n = 0;
      double first = 0, second = 0;  // the brightest and second brightest neighbours' luminance
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= image.width || yy >= image.height) continue;
          around[static_cast<std::size_t>(n++)] = source.pixel(xx, yy);
          const double l = luminance(around[static_cast<std::size_t>(n - 1)]);
          if (l > first) {
            second = first;
            first = l;
          } else {
            second = std::max(second, l);
          }
        }
      // On the border (fewer than 8 neighbours) always the brightest: a bright line that ends on
      // the border has one bright neighbour there.
      const double compared = rank == 2 && n == 8 ? second : first;
      const float* p = source.pixel(x, y);
      if (n < 3 || !(luminance(p) > ratio * compared)) continue;
      float* out = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        std::array<float, 8> v{};
        for (int k = 0; k < n; ++k) v[static_cast<std::size_t>(k)] = around[static_cast<std::size_t>(k)][c];
        std::nth_element(v.begin(), v.begin() + n / 2, v.begin() + n);
        out[c] = v[static_cast<std::size_t>(n / 2)];
      }
      ++replaced;
    }
  return replaced;
}

}  // namespace matlas::render
