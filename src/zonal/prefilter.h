#pragma once
// Per-band prefiltered environments: E_l(d) = integral L(w) Y_l^0(d . w) dw, the environment
// convolved with band l's zonal kernel. By the addition theorem (Funk-Hecke),
//
//     E_l(d) = sqrt(4pi/(2l+1)) sum_{m=-l..l} L_l^m Y_l^m(d),
//
// with L_l^m the environment's real SH coefficients. So a shading point's radiance is
// sum_{l,k} lambda_l^k(theta_o) E_l(R d_{l,k}) (docs/REALTIME.md).
//
// World frame as render::Environment: +y up; here theta = acos(d.y), phi = atan2(d.z, d.x) in
// [0, 2 pi). The SH coefficients are integrated on a lat-long grid `supersample` times finer
// than the map (each point reading Environment::eval, the renderer's piecewise-constant
// radiance, rotation and intensity included). E_l is tabulated on a lat-long grid of
// H_l = max(8, ceil(texels_per_band * (l + 1))) rows at theta = pi y / (H_l - 1) (the first and
// last rows are the poles) and W_l = 2 (H_l - 1) columns at phi = 2 pi x / W_l, and read
// bilinearly (periodic in phi): no clamping near the poles.
#include <vector>

#include "brdf/types.h"
#include "render/environment.h"

namespace matlas::zonal {

struct PrefilterSettings {
  int bands = 24;
  double texels_per_band = 8.0;
  int supersample = 2;
  /// Grid of a constant environment's SH integral (it has no map).
  int constant_grid = 64;
  /// Sharp lobes (zonal/lobes.h): one map per sharpness kappa_i, the environment convolved with
  /// the lobe, E_i(d) = sum_l k_l^i sum_m L_l^m Y_l^m(d) with the SH of the environment up to
  /// `lobe_bands` (each lobe stops where k_l < e^-9), tabulated on `lobe_rows` rows from pole to
  /// pole and 2 (lobe_rows - 1) columns, read bilinearly as the band maps. Empty: no lobe maps.
  std::vector<double> lobes = {};
  int lobe_bands = 256;
  int lobe_rows = 257;
  /// Rows per lobe in proportion to its width: lobe i gets 1 + (lobe_rows - 1) sqrt(kappa_i /
  /// kappa_max) rows (at least 65), the sharpest lobe_rows, so that bilinear reads err alike for
  /// every lobe (the error goes as (texel / lobe width)^2). Off: every lobe lobe_rows.
  bool scale_lobe_rows = false;
};

class PrefilteredEnvironment {
public:
  PrefilteredEnvironment(const render::Environment& env, const PrefilterSettings& settings);

  int bands() const { return settings_.bands; }
  /// E_l(d), d unit (world), bilinear in the tabulated map.
  Rgb lookup(int l, const Vec3& d) const;
  /// E_l(d) from the SH coefficients directly (exact, slow: tests and error measurements).
  Rgb exact(int l, const Vec3& d) const;
  /// Real SH coefficient L_l^m (m < 0: the sin(|m| phi) harmonic).
  Rgb coefficient(int l, int m) const;
  int map_width(int l) const { return 2 * (map_height(l) - 1); }
  int map_height(int l) const { return heights_[static_cast<std::size_t>(l)]; }
  /// Band l's map, RGB float, row-major from the +y pole: the texture layout of a shader.
  const std::vector<float>& map(int l) const { return maps_[static_cast<std::size_t>(l)]; }
  /// The lobes' sharpnesses (PrefilterSettings::lobes) and E_i(d), bilinear in lobe i's map.
  const std::vector<double>& lobes() const { return settings_.lobes; }
  Rgb lobe_lookup(std::size_t i, const Vec3& d) const;

private:
  PrefilterSettings settings_;
  std::vector<Rgb> cos_coeffs_, sin_coeffs_;  ///< [lm_index(l, m)]
  std::vector<int> heights_;
  std::vector<std::vector<float>> maps_;
  std::vector<std::vector<float>> lobe_maps_;  ///< lobe_heights_[i] x 2 (lobe_heights_[i] - 1), RGB
  std::vector<int> lobe_heights_;
};

}  // namespace matlas::zonal
