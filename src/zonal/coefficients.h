#pragma once
// The rotated-ZH coefficients lambda_l^k(theta_o) of one material, RGB, on a theta_o grid.
//
// Layout (also of the coefficient file and of a shader's texture): values[(t * S + j) * 3 + c]
// for theta_o sample t, coefficient j = lm_index(l, k) and channel c; S = K + M: after the K
// rotated-ZH coefficients come the M sharp-lobe weights c_i (zonal/lobes.h, j = K + i). The theta_o samples are
// the centres theta_t = (t + 0.5) (pi/2) / T; between them lambda is linear in theta_o, and
// clamped beyond the first and last.
#include <cstddef>
#include <vector>

#include "brdf/types.h"

namespace matlas::zonal {

struct ZonalCoefficients {
  int bands = 0;          ///< L
  int theta_o_count = 0;  ///< T
  std::vector<double> values;
  /// Sharpness kappa_i of each lobe (zonal/lobes.h); empty: the expansion alone. (After values:
  /// {bands, T, values} aggregates keep their meaning.)
  std::vector<double> lobes = {};

  /// K: the rotated-ZH coefficients per theta_o sample.
  std::size_t zonal_size() const { return static_cast<std::size_t>(bands + 1) * static_cast<std::size_t>(bands + 2) / 2; }
  /// S = K + M: every value per theta_o sample and channel.
  std::size_t size() const { return zonal_size() + lobes.size(); }
  static double theta_o(int t, int count) { return (t + 0.5) * (kPi / 2) / count; }
  Rgb at(int t, std::size_t j) const {
    const double* v = &values[(static_cast<std::size_t>(t) * size() + j) * 3];
    return {v[0], v[1], v[2]};
  }
  /// Interpolation in theta_o: samples t0 and t0 + 1 with weight (1 - f, f).
  void interpolation(double theta_o, int* t0, double* f) const;
  /// The coefficients interpolated at theta_o into out[3 j + c] (resized to 3 K).
  void interpolate(double theta_o, std::vector<double>& out) const;
};

/// sum_i w_i c_i over materials with the same layout (the map point of a convex or GP model:
/// coefficients are linear in the table). Throws matlas::Error for mismatched layouts.
ZonalCoefficients combine(const std::vector<const ZonalCoefficients*>& materials, const std::vector<double>& w);

}  // namespace matlas::zonal
