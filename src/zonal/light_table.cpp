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
  const HalfDiffAngles a = to_half_diff(wi, wo);
  const double u = std::clamp(theta_h_coordinate(a.theta_h, dims_.theta_h) - 0.5, 0.0, dims_.theta_h - 1.0);
  const double v = std::clamp(theta_d_coordinate(a.theta_d, dims_.theta_d) - 0.5, 0.0, dims_.theta_d - 1.0);
  double w = phi_d_coordinate(a.phi_d, dims_.phi_d) - 0.5;
  if (w < 0.0) w += dims_.phi_d;
  const int i0 = std::min(static_cast<int>(u), dims_.theta_h - 1), i1 = std::min(i0 + 1, dims_.theta_h - 1);
  const int j0 = std::min(static_cast<int>(v), dims_.theta_d - 1), j1 = std::min(j0 + 1, dims_.theta_d - 1);
  const int k0 = std::min(static_cast<int>(w), dims_.phi_d - 1), k1 = (k0 + 1) % dims_.phi_d;
  const double fu = u - i0, fv = v - j0, fw = w - k0;
  Rgb sum = Rgb::Zero();
  for (int corner = 0; corner < 8; ++corner) {
    const double wt = ((corner & 1) ? fu : 1 - fu) * ((corner & 2) ? fv : 1 - fv) * ((corner & 4) ? fw : 1 - fw);
    const std::size_t at =
        dims_.flat((corner & 1) ? i1 : i0, (corner & 2) ? j1 : j0, (corner & 4) ? k1 : k0) * 3;
    sum += wt * Rgb(values_[at], values_[at + 1], values_[at + 2]);
  }
  return sum;
}

LightTable LightTable::combine(const std::vector<const LightTable*>& parts, const std::vector<double>& weights) {
  MATLAS_CHECK_EQ(parts.size(), weights.size());
  if (parts.empty()) throw Error("light table: nothing to combine");
  LightTable out = *parts.front();
  std::fill(out.values().begin(), out.values().end(), 0.0f);
  std::vector<double> acc(out.values().size(), 0.0);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (!(parts[k]->dims() == out.dims())) throw Error("light table: tables of different grids combined");
    if (weights[k] == 0.0) continue;
    const std::vector<float>& v = parts[k]->values();
    for (std::size_t i = 0; i < v.size(); ++i) acc[i] += weights[k] * v[i];
  }
  for (std::size_t i = 0; i < acc.size(); ++i) out.values()[i] = static_cast<float>(acc[i]);
  return out;
}

}  // namespace matlas::zonal
