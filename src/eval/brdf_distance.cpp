#include "eval/brdf_distance.h"

#include <algorithm>

#include "core/error.h"

namespace matlas::eval {

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
