#include "zonal/coefficients.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/error.h"

namespace matlas::zonal {

void ZonalCoefficients::interpolation(double theta, int* t0, double* f) const {
  const double u = std::clamp(theta / (kPi / 2) * theta_o_count - 0.5, 0.0, theta_o_count - 1.0);
  *t0 = std::min(static_cast<int>(u), std::max(theta_o_count - 2, 0));
  *f = theta_o_count > 1 ? u - *t0 : 0.0;
}

void ZonalCoefficients::interpolate(double theta, std::vector<double>& out) const {
  const std::size_t n = 3 * size();
  MATLAS_DCHECK_EQ(values.size(), static_cast<std::size_t>(theta_o_count) * n);
  out.resize(n);
  int t0;
  double f;
  interpolation(theta, &t0, &f);
  const double* a = &values[static_cast<std::size_t>(t0) * n];
  if (f == 0.0) {
    std::copy(a, a + n, out.begin());
    return;
  }
  const double* b = a + n;
  for (std::size_t i = 0; i < n; ++i) out[i] = (1.0 - f) * a[i] + f * b[i];
}

ZonalCoefficients combine(const std::vector<const ZonalCoefficients*>& materials, const std::vector<double>& w) {
  MATLAS_CHECK(!materials.empty());
  MATLAS_CHECK_EQ(materials.size(), w.size());
  ZonalCoefficients out = *materials[0];
  std::fill(out.values.begin(), out.values.end(), 0.0);
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const ZonalCoefficients& m = *materials[i];
    MATLAS_CHECK(m.bands == out.bands && m.theta_o_count == out.theta_o_count && m.lobes == out.lobes &&
                     m.values.size() == out.values.size(),
                 "every material of a combination has one layout");
    for (std::size_t v = 0; v < out.values.size(); ++v) out.values[v] += w[i] * m.values[v];
  }
  return out;
}

}  // namespace matlas::zonal
