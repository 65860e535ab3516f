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
  const TrilinearBins t = trilinear_bins(dims_, wi, wo);
  Rgb sum = Rgb::Zero();
  Rgb weight = Rgb::Zero();
  for (std::size_t corner = 0; corner < 8; ++corner) {
    const double wt = t.weights[corner];
    if (wt == 0.0) continue;
    for (int c = 0; c < kChannels; ++c) {
      if (!measured(c, t.bins[corner])) continue;
      sum[c] += wt * value(c, t.bins[corner]);
      weight[c] += wt;
    }
  }
  return (weight > 0.0).select(sum / weight.max(1e-300), Rgb::Zero());
}

}  // namespace matlas
