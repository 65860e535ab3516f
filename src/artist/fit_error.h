#pragma once
// How far a fitted analytic model is from the table it was fitted to, in the measures the export
// check uses (formats/rgl_export_check.h) so that the two can be compared: the cosine-weighted
// relative RMS and the directional albedo at 0-75 deg, plus the evaluation's cube-root distance.
#include <vector>

#include "brdf/brdf_table.h"
#include "brdf/tabulate.h"

namespace matlas::artist {

struct FitErrorOptions {
  std::vector<double> angles_deg{0, 15, 30, 45, 60, 75};  ///< view angles of the albedo comparison
  int albedo_resolution = 540;  ///< half-vector quadrature (brdf/albedo.h's half_vector_albedo)
};

struct FitError {
  /// sqrt(sum (c (f_fit - f_table))^2 / sum (c f_table)^2) over the table's measured bins (their
  /// centres), channels summed, c = cos(theta_i) cos(theta_o) (eval/brdf_distance.h's RMSE,
  /// relative).
  double relative_rms = 0;
  /// Fores et al.'s cube-root distance (eval/brdf_distance.h) over the same values: what the fit
  /// minimises (on a subsample).
  double cbrt_distance = 0;
  std::vector<double> angles_deg;
  /// Directional albedo of the table (its smooth lookup) and of the fit at each angle.
  std::vector<Rgb> table_albedo, fit_albedo;
  /// Largest |fit - table| / max(table, 0.01) over angles and channels.
  double albedo_error = 0;
};

/// `model`: the fitted BRDF (GltfPbr, PrincipledV1 or any f(wi, wo) in the local frame).
FitError fit_error(const BrdfTable& table, const BrdfFunction& model, const FitErrorOptions& options = {});

}  // namespace matlas::artist
