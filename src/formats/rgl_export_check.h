#pragma once
// How faithfully an RGL `.bsdf` file, evaluated as the format defines (formats/rgl_bsdf.h, which
// agrees with RGL's loader), reproduces the MERL table it was written from, and how well its own
// importance sampling works: the export's self-check (docs/EXPORT.md).
#include <cstdint>
#include <vector>

#include "brdf/brdf_table.h"
#include "formats/rgl_bsdf.h"

namespace matlas {

struct RglFidelityOptions {
  std::vector<double> angles_deg{0, 15, 30, 45, 60, 75};  ///< view angles of the albedo checks
  int albedo_resolution = 540;   ///< half-vector quadrature (brdf/albedo.h's half_vector_albedo)
  int samples = 8192;            ///< Monte Carlo samples per angle for the sampling check
  std::uint64_t seed = 1;
};

struct RglFidelity {
  /// The cosine-weighted RMSE of matlas' evaluation (eval/brdf_distance.h) relative to the
  /// table's own: sqrt(sum (c (f_file - f_table))^2 / sum (c f_table)^2) over the table's measured
  /// bins (their centres), channels summed, c = cos(theta_i) cos(theta_o).
  double relative_rms = 0;
  /// The same between the bin centres, against the table's smooth lookup (trilinear between the
  /// centres): at one point per bin, uniform over the bin's coordinates (a fixed sequence from
  /// `seed`), where the eight bins of the lookup are measured. What a renderer sees besides the
  /// centres: a file fitted at given points (formats/rgl_sample_fit.h) that oscillated between
  /// them would show here.
  double relative_rms_between = 0;
  std::vector<double> angles_deg;
  /// Directional albedo at each angle: of the table (its smooth lookup, the function written)
  /// and of the file (as a renderer integrates it: the view is the file's first direction).
  std::vector<Rgb> table_albedo, file_albedo;
  /// Largest |file - table| / max(table, 0.01) over angles and channels.
  double albedo_error = 0;
  /// Monte Carlo estimates of the luminance albedo per angle: mean with the file's own sampling,
  /// and the variance of one sample's estimate with it and with cosine sampling.
  std::vector<double> sampled_albedo, variance_own, variance_cosine;
};

RglFidelity check_rgl_fidelity(const RglBsdf& file, const BrdfTable& table, const RglFidelityOptions& options = {});

}  // namespace matlas
