#pragma once
// Deterministic sampling: a counter-based random number source (the same numbers for a given
// seed, pixel, sample and dimension whatever the thread schedule), piecewise-constant
// distributions, and the direction warps of the fixed sampling mixture.
#include <cstdint>
#include <span>
#include <vector>

#include "brdf/types.h"

namespace matlas::render {

/// Uniform numbers in [0, 1) from a hash of (seed, pixel, sample, dimension).
class SampleStream {
public:
  SampleStream(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
      : key_(mix(seed ^ mix(pixel * 0x9E3779B97F4A7C15ull + sample))) {}
  /// The next number of this stream.
  double next() { return to_unit(mix(key_ + 0xD1B54A32D192ED03ull * ++counter_)); }

  static std::uint64_t mix(std::uint64_t z) {  // splitmix64 finaliser
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  static double to_unit(std::uint64_t z) { return static_cast<double>(z >> 11) * 0x1.0p-53; }

private:
  std::uint64_t key_;
  std::uint64_t counter_ = 0;
};

/// A piecewise-constant distribution on [0, 1) with `size` cells.
class Distribution1D {
public:
  Distribution1D() = default;
  /// Non-negative weights; all zero gives the uniform distribution.
  explicit Distribution1D(std::span<const double> weights);
  /// Sample: returns the continuous position in [0, 1) and the cell; pdf w.r.t. [0, 1).
  double sample(double u, int* cell, double* pdf) const;
  double pdf(int cell) const { return weights_[static_cast<std::size_t>(cell)] / integral_; }
  int size() const { return static_cast<int>(weights_.size()); }
  double integral() const { return integral_; }  ///< mean weight

private:
  double cell_width() const { return 1.0 / static_cast<double>(weights_.size()); }
  std::vector<double> weights_, cdf_;
  double integral_ = 0;
};

/// A piecewise-constant distribution on [0, 1)^2 (rows of columns), for environment maps.
class Distribution2D {
public:
  Distribution2D() = default;
  /// weights[row * cols + col] >= 0.
  Distribution2D(std::span<const double> weights, int cols, int rows);
  /// (u, v) in [0, 1)^2, with the density w.r.t. the unit square.
  void sample(double u0, double u1, double* u, double* v, double* pdf) const;
  double pdf(double u, double v) const;

private:
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
  int cols_ = 0, rows_ = 0;
};

/// Builds an orthonormal basis (t, b, n) around the unit vector n (Duff et al. 2017).
void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b);

/// Cosine-weighted hemisphere direction (local frame, +z up); pdf = cos(theta) / pi.
Vec3 sample_cosine(double u0, double u1);
inline double cosine_pdf(const Vec3& w) { return w.z() > 0 ? w.z() / kPi : 0.0; }

/// Reflected direction from a GGX half vector of width `alpha` (D(h) cos(theta_h) sampling) for
/// the view direction wo (local, z > 0). The pdf of the result is ggx_reflection_pdf.
Vec3 sample_ggx_reflection(const Vec3& wo, double alpha, double u0, double u1);
double ggx_reflection_pdf(const Vec3& wo, const Vec3& wi, double alpha);

}  // namespace matlas::render
