#pragma once
// The piecewise-bilinear 2D distributions of the RGL measured BSDF model (Dupuy & Jakob 2018),
// with the same semantics as Mitsuba's Marginal2D (continuous variant), written from the maths:
//
// A slice is an nx x ny grid of values on the corners of (nx-1) x (ny-1) equal patches covering
// [0,1]^2 (x contiguous); between corners it is bilinear. A table may hold several slices, one per
// combination of parameter values (e.g. the incident angles theta_i, phi_i); lookups blend
// neighbouring slices linearly in each parameter (ParamBlend).
//
// With CDFs built, each slice is normalised to a probability density on [0,1]^2 and the warp
// maps [0,1]^2 onto itself: sample() draws y from the marginal density of rows and then x from
// the conditional density of that row; invert() is its exact inverse (the marginal CDF of y and
// the conditional CDF of x given y). The measured model evaluates through invert(): the VNDF's
// inverse warp takes the half vector to the coordinates where the reflectance tables are stored.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace matlas {

/// Up to two interpolated parameters: at most four slices with weights summing to 1.
struct ParamBlend {
  int count = 1;
  std::array<std::size_t, 4> slice{};
  std::array<double, 4> weight{1.0, 0.0, 0.0, 0.0};
};

/// Interpolation weights along one parameter axis with sorted sample positions `values`: the
/// interval [values[i], values[i+1]] holding x (clamped to the ends; a single value means no
/// dependence). Returns {i, weight of i+1}.
std::pair<std::size_t, double> param_interval(std::span<const float> values, double x);

/// Blend of slices of a table laid out as [outer][inner] parameter values (outer slowest).
/// `outer` may be empty (no outer parameter).
ParamBlend blend_params(std::span<const float> outer, double outer_x, std::span<const float> inner,
                        double inner_x);

class RglWarp2D {
public:
  RglWarp2D() = default;
  /// `data` holds slices * ny * nx values. nx, ny >= 2. With build_cdf, every slice must have a
  /// positive integral (the caller checks, naming the file).
  RglWarp2D(std::span<const float> data, std::size_t nx, std::size_t ny, std::size_t slices, bool build_cdf);
  /// A table without CDFs that keeps `data` as it is (single precision, moved in: no copy).
  /// Lookups give the same values as from a copy in double precision.
  RglWarp2D(std::vector<float>&& data, std::size_t nx, std::size_t ny, std::size_t slices);

  std::size_t nx() const { return nx_; }
  std::size_t ny() const { return ny_; }
  std::size_t slices() const { return slices_; }
  /// Integral of slice s over [0,1]^2 before normalisation (0 if not built with CDFs).
  double slice_integral(std::size_t s) const { return integral_.empty() ? 0.0 : integral_[s]; }

  /// The grid cell holding (x, y) (clamped to [0,1]^2): its lower corner (px, py) and the
  /// position inside it (s, t). Every lookup interpolates the cell's corners (px, py), (px+1, py),
  /// (px, py+1), (px+1, py+1) with weights (1-s)(1-t), s(1-t), (1-s)t, st: a raw table's eval()
  /// is linear in its values with these weights (what fitting a table's values needs).
  struct Cell {
    std::size_t px, py;
    double s, t;
    /// The corners' weights in that order.
    std::array<double, 4> weights() const { return {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t}; }
  };
  Cell cell(double x, double y) const;

  /// Bilinear interpolation at (x, y) in [0,1]^2 (clamped): the raw values, or the normalised
  /// density when built with CDFs.
  double eval(double x, double y, const ParamBlend& blend) const;
  /// Inverse of sample(): (conditional CDF of x given y, marginal CDF of y).
  std::array<double, 2> invert(double x, double y, const ParamBlend& blend) const;
  /// The sampling warp: uniform (u, v) in [0,1]^2 to a point distributed by the density.
  std::array<double, 2> sample(double u, double v, const ParamBlend& blend) const;

private:
  /// The grid cell holding (x, y) (clamped to [0,1]^2): its first index, position inside the
  /// cell (s, t) and the four corner values of the blended slices.
  struct Patch {
    std::size_t px, py, index;
    double s, t, v00, v10, v01, v11;
  };
  Patch patch(double x, double y, const ParamBlend& b) const;

  template <class T>
  double at(const std::vector<T>& values, std::size_t stride, std::size_t index, const ParamBlend& b) const {
    double sum = 0;
    for (int i = 0; i < b.count; ++i) sum += b.weight[i] * static_cast<double>(values[b.slice[i] * stride + index]);
    return sum;
  }
  /// Value `index` of the table (blended slices), from whichever of data_ and raw_ holds it.
  double value(std::size_t index, const ParamBlend& b) const {
    return raw_.empty() ? at(data_, nx_ * ny_, index, b) : at(raw_, nx_ * ny_, index, b);
  }

  std::size_t nx_ = 0, ny_ = 0, slices_ = 0;
  std::vector<double> data_;         ///< slices * ny * nx (normalised when CDFs are built)
  std::vector<float> raw_;           ///< instead of data_ for tables without CDFs
  std::vector<double> conditional_;  ///< per slice and row: integral from x = 0 to each column
  std::vector<double> marginal_;     ///< per slice: integral from y = 0 to each row
  std::vector<double> integral_;     ///< per slice, before normalisation
};

}  // namespace matlas
