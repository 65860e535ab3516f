#include "zonal/compare.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace matlas::zonal {

ImageErrors compare_to_reference(const Image& z, const Image& r1, const Image& r2, const std::vector<float>& coverage) {
  if (z.rgb.size() != r1.rgb.size() || z.rgb.size() != r2.rgb.size() || z.rgb.size() != 3 * coverage.size())
    throw Error("image comparison: sizes differ");
  double abs_err = 0, sq_err = 0, abs_ref = 0, sq_ref = 0, abs_noise = 0, sq_noise = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f)
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t i = 3 * p + c;
        const double r = 0.5 * (static_cast<double>(r1.rgb[i]) + r2.rgb[i]), d = z.rgb[i] - r;
        const double n = static_cast<double>(r1.rgb[i]) - r2.rgb[i];
        abs_err += std::abs(d);
        sq_err += d * d;
        abs_ref += std::abs(r);
        sq_ref += r * r;
        abs_noise += std::abs(n);
        sq_noise += n * n;
      }
  if (!(abs_ref > 0)) throw Error("image comparison: no covered pixel with light");
  return {abs_err / abs_ref, std::sqrt(std::max(0.0, sq_err - sq_noise / 4) / sq_ref), abs_noise / 2 / abs_ref};
}

}  // namespace matlas::zonal
