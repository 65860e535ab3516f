#include "brdf/tabulate.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/parallel.h"

namespace matlas {

BrdfTable tabulate_function(const BrdfFunction& f, MerlDims dims) {
  BrdfTable table(dims);  // every value 0: below-horizon bins stay so
  const std::size_t rows = static_cast<std::size_t>(dims.theta_h) * static_cast<std::size_t>(dims.theta_d);
  parallel_for(0, rows, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t row = lo; row < hi; ++row) {
      const int i = static_cast<int>(row / static_cast<std::size_t>(dims.theta_d));
      const int j = static_cast<int>(row % static_cast<std::size_t>(dims.theta_d));
      for (int k = 0; k < dims.phi_d; ++k) {
        const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
        if (d.wi.z() <= 0.0 || d.wo.z() <= 0.0) continue;
        const Rgb v = f(d.wi, d.wo);
        const std::size_t bin = dims.flat(i, j, k);
        for (int c = 0; c < BrdfTable::kChannels; ++c) {
          if (!(std::isfinite(v[c]) && v[c] >= 0.0))
            throw Error("tabulate: the BRDF returned " + std::to_string(v[c]) + " in channel " +
                        std::to_string(c) + " at bin (" + std::to_string(i) + ", " + std::to_string(j) +
                        ", " + std::to_string(k) + "); values must be finite and >= 0");
          table.set_value(c, bin, v[c]);
        }
      }
    }
  });
  return table;
}

}  // namespace matlas
