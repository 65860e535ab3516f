#pragma once
// The BRDF as the real-time viewer's direct lights read it (zonal/light_split.h): a table on the
// MERL grid with theta_h and theta_d kept and phi_d averaged over groups of bins (15 bins of 12
// degrees from MERL's 180; on other grids the fewest equal groups that leave at most 15), read by trilinear interpolation between bin centres as a shader's
// 3D texture does (theta_h in its square-root coordinate, theta edges clamped, phi_d periodic
// with period pi). Values of bins without any measurement are filled with the nearest measured
// value below them in theta_h (0 where the column has none), so that interpolation near the
// measured region's edge does not mix in zeros.
//
// Linear in the table: the light table of a weighted sum of tables is the same weighted sum of
// their light tables, so a map point's is combined from the materials' (atlas/model_light_tables.h).
// docs/REALTIME.md "Direct lights" measures the resolution (phi_d 15 bins: as accurate as 180
// under `studio`; theta_d halved costs 0.6 points).
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "brdf/brdf_table.h"
#include "brdf/types.h"
#include "render/material.h"

namespace matlas::zonal {

/// The most phi_d bins of a light table.
inline constexpr int kLightTablePhi = 15;

class LightTable {
public:
  /// Zeros on `dims` (a reduced grid: phi_d <= kLightTablePhi).
  explicit LightTable(const MerlDims& dims);
  /// The reduced grid of a table on `full`: phi_d / g bins for the least g >= phi_d / 15 that
  /// divides phi_d (MERL's 180: 15).
  static MerlDims reduced_dims(const MerlDims& full);
  static LightTable reduce(const BrdfTable& table);
  /// The same from values read by `value(channel, bin)` on the grid `dims`, NaN where missing.
  static LightTable reduce(const MerlDims& dims, const std::function<double(int channel, std::size_t bin)>& value);

  const MerlDims& dims() const { return dims_; }
  /// RGB per bin, [theta_h][theta_d][phi_d][channel]: a shader's 3D texture (phi_d fastest).
  const std::vector<float>& values() const { return values_; }
  std::vector<float>& values() { return values_; }

  /// f(wi, wo) in the local frame (z = normal), trilinear as the shader reads it.
  Rgb eval(const Vec3& wi, const Vec3& wo) const;

private:
  MerlDims dims_;
  std::vector<float> values_;
};


/// A light table as a renderer material (zonal::shade_lights, tests).
class LightTableMaterial final : public render::Material {
public:
  explicit LightTableMaterial(const LightTable& table) : table_(table) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return table_.eval(wi, wo); }

private:
  const LightTable& table_;
};

}  // namespace matlas::zonal
