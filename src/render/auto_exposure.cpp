#include "render/auto_exposure.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace matlas::render {

double auto_exposure(const Image& image, const std::vector<bool>& mask) {
  MATLAS_CHECK(mask.empty() || mask.size() == image.pixel_count());
  double log_sum = 0;
  std::size_t count = 0;
  bool any_light = false;
  for (std::size_t p = 0; p < image.pixel_count(); ++p) {
    if (!mask.empty() && !mask[p]) continue;
    const float* v = image.rgb.data() + 3 * p;
    const double l = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
    if (!std::isfinite(l)) continue;
    any_light |= l > 0;
    log_sum += std::log(1e-4 + std::max(0.0, l));
    ++count;
  }
  if (count == 0 || !any_light) return 0.0;
  const double average = std::exp(log_sum / static_cast<double>(count));
  return std::clamp(std::log2(0.18 / average), -16.0, 16.0);
}

}  // namespace matlas::render
