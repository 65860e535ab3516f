#pragma once
// BrdfTable: an isotropic RGB BRDF tabulated on the MERL half/difference grid.
//
// Values are kept exactly as a MERL file stores them ("stored units": the physical value divided
// by the channel scale), so a file read and written again is bit-identical, and physical values
// are stored * channel_scale(c), exactly as MERL's reference reader computes them. A negative
// stored value means "no measurement" (MERL writes -1 below the horizon): it is a mask, never a
// value, and every accessor says so.
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "brdf/merl_grid.h"
#include "brdf/value_buffer.h"

namespace matlas {

class BrdfTable {
public:
  /// MERL's channel scales (BRDFRead.cpp): physical = stored * scale.
  static constexpr std::array<double, 3> kChannelScale = {1.0 / 1500.0, 1.15 / 1500.0,
                                                          1.66 / 1500.0};
  static constexpr int kChannels = 3;

  BrdfTable() = default;
  /// A table of the given size with every value 0 and measured.
  explicit BrdfTable(MerlDims dims);
  /// A table whose values are unspecified, for a caller that fills every value (file readers).
  BrdfTable(MerlDims dims, ValueBuffer::Uninitialized);

  const MerlDims& dims() const { return dims_; }
  std::size_t bins() const { return dims_.bins(); }
  /// Number of values (3 * bins).
  std::size_t size() const { return stored_.size(); }

  /// All values in stored units, channel-major: red block, green block, blue block.
  std::span<const double> stored() const { return stored_; }
  std::span<double> stored() { return stored_; }

  bool measured(int channel, std::size_t bin) const { return stored_[offset(channel, bin)] >= 0.0; }
  /// Physical value; only meaningful where measured().
  double value(int channel, std::size_t bin) const {
    return stored_[offset(channel, bin)] * kChannelScale[static_cast<std::size_t>(channel)];
  }
  void set_value(int channel, std::size_t bin, double physical) {
    stored_[offset(channel, bin)] = physical / kChannelScale[static_cast<std::size_t>(channel)];
  }
  void set_missing(int channel, std::size_t bin) { stored_[offset(channel, bin)] = -1.0; }

  /// Number of (channel, bin) values without a measurement.
  std::size_t missing_count() const;

  /// Physical RGB of one bin; channels without a measurement read as 0 and clear *all_measured.
  Rgb bin_rgb(std::size_t bin, bool* all_measured = nullptr) const;

  /// f(wi, wo) with MERL's reference nearest-bin lookup. Directions are unit vectors in the local
  /// frame (normal +z). Missing values read as 0 and clear *all_measured when given.
  Rgb lookup(const Vec3& wi, const Vec3& wo, bool* all_measured = nullptr) const;

  /// Smooth lookup: trilinear interpolation between bin centres (theta_h in its square-root
  /// coordinate, phi_d periodic with period pi, clamped at the theta edges). Missing neighbours
  /// are left out and the weights of the others renormalised.
  Rgb lookup_smooth(const Vec3& wi, const Vec3& wo) const;

private:
  std::size_t offset(int channel, std::size_t bin) const {
    return static_cast<std::size_t>(channel) * dims_.bins() + bin;
  }

  MerlDims dims_{};
  ValueBuffer stored_;
};

}  // namespace matlas
