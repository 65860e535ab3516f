#pragma once
// BRDF distances used by the evaluation (docs/EVALUATION.md, "Metrics").
//
// Both are computed over the values (channel, bin) of the MERL grid that are measured in both
// tables and whose bin centre lies above the horizon for both directions, with
// c_b = cos(theta_i) cos(theta_o) at the centre of bin b:
//
//   cube-root distance (Fores et al. 2012, cosine-weighted cube-root metric):
//       d_cbrt(f, g) = sqrt( mean over values of ( cbrt(c_b f) - cbrt(c_b g) )^2 )
//   cosine-weighted RMSE:
//       d_rmse(f, g) = sqrt( mean over values of ( c_b (f - g) )^2 )
//
// f and g are physical values. The cube root is the signed one, so a negative interpolated value
// counts as the error it is instead of being hidden by a clamp. Both distances are symmetric, zero
// exactly for identical tables, and satisfy the triangle inequality (they are L2 norms of
// transformed tables).
#include <cmath>
#include <cstddef>
#include <vector>

#include "brdf/brdf_table.h"

namespace matlas::eval {

/// c_b = max(0, cos(theta_i) cos(theta_o)) at the centre of every bin: matlas::bin_cosine_factors
/// (brdf/merl_grid.h).
using matlas::bin_cosine_factors;

/// The two distances between a pair of tables.
struct BrdfDistance {
  double cbrt_cosine = 0;  ///< Fores cube-root, cosine-weighted distance
  double cosine_rmse = 0;  ///< cosine-weighted RMSE (physical units)
  std::size_t values = 0;  ///< number of values compared
};

/// Running sums of squared differences from which a BrdfDistance is finished.
struct DistanceSums {
  double cbrt_squared = 0;
  double cosine_squared = 0;
  std::size_t values = 0;

  /// Adds one value pair: f and g physical, c the bin's cosine factor (> 0).
  void add(double f, double g, double c) {
    const double a = std::cbrt(c * f) - std::cbrt(c * g);
    const double b = c * (f - g);
    cbrt_squared += a * a;
    cosine_squared += b * b;
    ++values;
  }
  BrdfDistance finish() const;
};

/// Distance between two tables of the same dims (throws matlas::Error otherwise).
BrdfDistance brdf_distance(const BrdfTable& a, const BrdfTable& b);

}  // namespace matlas::eval
