#include "eval/brdf_distance.h"

#include <algorithm>

#include "core/error.h"

namespace matlas::eval {

std::vector<double> bin_cosine_factors(const MerlDims& dims) {
  std::vector<double> c(dims.bins());
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
        c[dims.flat(i, j, k)] = std::max(0.0, d.wi.z()) * std::max(0.0, d.wo.z());
      }
  return c;
}

BrdfDistance DistanceSums::finish() const {
  BrdfDistance d;
  d.values = values;
  if (values > 0) {
    d.cbrt_cosine = std::sqrt(cbrt_squared / static_cast<double>(values));
    d.cosine_rmse = std::sqrt(cosine_squared / static_cast<double>(values));
  }
  return d;
}

BrdfDistance brdf_distance(const BrdfTable& a, const BrdfTable& b) {
  if (!(a.dims() == b.dims()))
    throw Error("brdf_distance: tables of different dims (" + a.dims().to_string() + " and " +
                b.dims().to_string() + ")");
  const std::vector<double> cosine = bin_cosine_factors(a.dims());
  DistanceSums sums;
  for (int ch = 0; ch < BrdfTable::kChannels; ++ch)
    for (std::size_t bin = 0; bin < a.bins(); ++bin)
      if (cosine[bin] > 0 && a.measured(ch, bin) && b.measured(ch, bin))
        sums.add(a.value(ch, bin), b.value(ch, bin), cosine[bin]);
  return sums.finish();
}

}  // namespace matlas::eval
