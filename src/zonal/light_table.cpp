#include "zonal/light_table.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "brdf/merl_grid.h"
#include "core/check.h"
#include "core/error.h"

namespace matlas::zonal {

LightTable::LightTable(const MerlDims& dims) : dims_(dims), values_(dims.bins() * 3, 0.0f) {
  MATLAS_CHECK(dims.phi_d >= 1 && dims.phi_d <= kLightTablePhi);
}

MerlDims LightTable::reduced_dims(const MerlDims& full) {
  MATLAS_CHECK(full.theta_h >= 1 && full.theta_d >= 1 && full.phi_d >= 1);
  int group = (full.phi_d + kLightTablePhi - 1) / kLightTablePhi;
  while (full.phi_d % group != 0) ++group;
  return {full.theta_h, full.theta_d, full.phi_d / group};
}

LightTable LightTable::reduce(const BrdfTable& table) {
  return reduce(table.dims(), [&](int channel, std::size_t bin) {
    return table.measured(channel, bin) ? table.value(channel, bin) : std::nan("");
  });
}

LightTable LightTable::reduce(const MerlDims& dims, const std::function<double(int, std::size_t)>& value) {
  LightTable out(reduced_dims(dims));
  const int group = dims.phi_d / out.dims_.phi_d;
  std::vector<bool> measured(out.dims_.bins() * 3, false);
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < out.dims_.phi_d; ++k)
        for (int c = 0; c < 3; ++c) {
          double sum = 0.0;
          int n = 0;
          for (int e = 0; e < group; ++e) {
            const double v = value(c, dims.flat(i, j, k * group + e));
            if (std::isnan(v)) continue;
            sum += v;
            ++n;
          }
          const std::size_t at = out.dims_.flat(i, j, k) * 3 + static_cast<std::size_t>(c);
          if (n) {
            out.values_[at] = static_cast<float>(sum / n);
            measured[at] = true;
          }
        }
  // Missing bins take the nearest measured value below them in theta_h (MERL's unmeasured bins
  // lie beyond the measured ones in theta_h at large theta_d).
  for (int j = 0; j < dims.theta_d; ++j)
    for (int k = 0; k < out.dims_.phi_d; ++k)
      for (int c = 0; c < 3; ++c) {
        float last = 0.0f;
        for (int i = 0; i < dims.theta_h; ++i) {
          const std::size_t at = out.dims_.flat(i, j, k) * 3 + static_cast<std::size_t>(c);
          if (measured[at]) last = out.values_[at];
          else out.values_[at] = last;
        }
      }
  return out;
}

Rgb LightTable::eval(const Vec3& wi, const Vec3& wo) const {
  const TrilinearBins t = trilinear_bins(dims_, wi, wo);
  Rgb sum = Rgb::Zero();
  for (std::size_t corner = 0; corner < 8; ++corner) {
    const std::size_t at = t.bins[corner] * 3;
    sum += t.weights[corner] * Rgb(values_[at], values_[at + 1], values_[at + 2]);
  }
  return sum;
}

}  // namespace matlas::zonal
