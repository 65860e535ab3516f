#include "formats/image_resize.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace matlas {

namespace {
/// For each output index, the input indices and weights along one axis.
struct Taps {
  std::vector<int> first, count;
  std::vector<double> weight;  // concatenated
  std::vector<int> offset;
};

Taps taps(int in, int out) {
  Taps t;
  const double scale = static_cast<double>(in) / out;
  for (int o = 0; o < out; ++o) {
    const double a = o * scale, b = (o + 1) * scale;
    const int i0 = static_cast<int>(std::floor(a)), i1 = std::min(in, static_cast<int>(std::ceil(b)));
    t.first.push_back(i0);
    t.count.push_back(i1 - i0);
    t.offset.push_back(static_cast<int>(t.weight.size()));
    for (int i = i0; i < i1; ++i) {
      const double overlap = std::min<double>(b, i + 1) - std::max<double>(a, i);
      t.weight.push_back(overlap / scale);
    }
  }
  return t;
}
}  // namespace

Image resize_area(const Image& image, int width, int height) {
  if (width == image.width && height == image.height) return image;
  const Taps tx = taps(image.width, width), ty = taps(image.height, height);
  Image out(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double acc[3] = {0, 0, 0};
      for (int j = 0; j < ty.count[static_cast<std::size_t>(y)]; ++j) {
        const double wy = ty.weight[static_cast<std::size_t>(ty.offset[static_cast<std::size_t>(y)] + j)];
        for (int i = 0; i < tx.count[static_cast<std::size_t>(x)]; ++i) {
          const double w = wy * tx.weight[static_cast<std::size_t>(tx.offset[static_cast<std::size_t>(x)] + i)];
          const float* p = image.pixel(tx.first[static_cast<std::size_t>(x)] + i, ty.first[static_cast<std::size_t>(y)] + j);
          for (int c = 0; c < 3; ++c) acc[c] += w * p[c];
        }
      }
      float* q = out.pixel(x, y);
      for (int c = 0; c < 3; ++c) q[c] = static_cast<float>(acc[c]);
    }
  return out;
}

}  // namespace matlas
