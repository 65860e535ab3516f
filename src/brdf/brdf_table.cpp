#include "brdf/brdf_table.h"

#include <algorithm>
#include <cmath>

namespace matlas {

BrdfTable::BrdfTable(MerlDims dims) : dims_(dims), stored_(3 * dims.bins()) {}

BrdfTable::BrdfTable(MerlDims dims, ValueBuffer::Uninitialized u) : dims_(dims), stored_(3 * dims.bins(), u) {}

std::size_t BrdfTable::missing_count() const {
  return static_cast<std::size_t>(
      std::count_if(stored_.begin(), stored_.end(), [](double v) { return v < 0.0; }));
}

Rgb BrdfTable::bin_rgb(std::size_t bin, bool* all_measured) const {
  Rgb rgb;
  for (int c = 0; c < kChannels; ++c) {
    if (measured(c, bin)) {
      rgb[c] = value(c, bin);
    } else {
      rgb[c] = 0.0;
      if (all_measured) *all_measured = false;
    }
  }
  return rgb;
}

Rgb BrdfTable::lookup(const Vec3& wi, const Vec3& wo, bool* all_measured) const {
  if (all_measured) *all_measured = true;
  return bin_rgb(bin_of(dims_, wi, wo), all_measured);
}

Rgb BrdfTable::lookup_smooth(const Vec3& wi, const Vec3& wo) const {
  const HalfDiffAngles a = to_half_diff(wi, wo);
  // Coordinates relative to bin centres: bin i's centre sits at u = i.
  const double u = std::clamp(theta_h_coordinate(a.theta_h, dims_.theta_h) - 0.5, 0.0,
                              dims_.theta_h - 1.0);
  const double v = std::clamp(theta_d_coordinate(a.theta_d, dims_.theta_d) - 0.5, 0.0,
                              dims_.theta_d - 1.0);
  double w = phi_d_coordinate(a.phi_d, dims_.phi_d) - 0.5;
  if (w < 0.0) w += dims_.phi_d;
  const int i0 = std::min(static_cast<int>(u), dims_.theta_h - 1);
  const int j0 = std::min(static_cast<int>(v), dims_.theta_d - 1);
  const int k0 = std::min(static_cast<int>(w), dims_.phi_d - 1);
  const double fu = u - i0, fv = v - j0, fw = w - k0;
  const int i1 = std::min(i0 + 1, dims_.theta_h - 1);
  const int j1 = std::min(j0 + 1, dims_.theta_d - 1);
  const int k1 = (k0 + 1) % dims_.phi_d;

  Rgb sum = Rgb::Zero();
  Rgb weight = Rgb::Zero();
  for (int corner = 0; corner < 8; ++corner) {
    const double wt = ((corner & 1) ? fu : 1 - fu) * ((corner & 2) ? fv : 1 - fv) *
                      ((corner & 4) ? fw : 1 - fw);
    if (wt == 0.0) continue;
    const std::size_t bin = dims_.flat((corner & 1) ? i1 : i0, (corner & 2) ? j1 : j0,
                                       (corner & 4) ? k1 : k0);
    for (int c = 0; c < kChannels; ++c) {
      if (!measured(c, bin)) continue;
      sum[c] += wt * value(c, bin);
      weight[c] += wt;
    }
  }
  return (weight > 0.0).select(sum / weight.max(1e-300), Rgb::Zero());
}

}  // namespace matlas
