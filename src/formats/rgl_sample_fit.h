#pragma once
// Fitting the reflectance samples of an RGL `.bsdf` file to the MERL table it is written from, in
// least squares (docs/EXPORT.md).
//
// A file evaluated as the format defines (formats/rgl_bsdf.h) is linear in its reflectance
// samples: at a pair of directions it interpolates the samples bilinearly at the point of the
// unit square where the VNDF's inverse warp puts the half vector, linearly between the two
// incident elevations around wi, and multiplies by the Jacobian D(m) / (4 sigma(wi)). Samples
// taken from the table at the nodes (the writer's first pass) are exact at the elevations and
// points written and off by the interpolation error between them: where the table is curved (a
// peak that grows fast with theta_i, a narrow highlight across a few cells), linear interpolation
// of point samples stays on one side of it. Here the samples are instead the least-squares
// solution of
//
//   min over samples  sum over points p, channels c of
//                     (cos(theta_i) cos(theta_o) (f_file(wi_p, wo_p) - f_table(p)))^2
//
// at the table's measured bin centres (its data, weighted as matlas' cosine-weighted RMSE,
// eval/brdf_distance.h) and at the corners where eight measured bins meet (the table's smooth
// lookup there: fitted at the centres alone, the file drifted away from the table between them),
// plus a damping term lambda |samples - point samples|^2, by conjugate gradients on the normal
// equations started from the point samples: samples no point reaches keep their point values and
// those few reach stay near them. The slice at normal incidence is not fitted: a renderer sees it
// alone at theta_i = 0, where no bin centre lies, and fitted only through the interval above it,
// it bent the albedo at 0 deg by up to 4 %. Samples the fit takes below 0 (the reader clips the
// interpolated value at 0) are then held at 0 and the others fitted again, half as many
// iterations. Besides the points, rows ask for the file's directional albedo (as a renderer
// integrates it) to be the table's at every elevation and midway between: the points alone left a
// pearlescent whose albedo changes fast with the angle 1.55 % off between elevations. The normal
// equations' transpose products scatter into the two elevations around each
// point: points are grouped by their lower elevation, and the even groups, then the odd ones, run
// in parallel without sharing a sample, so the result does not depend on the number of threads
// (the forward products and sums run in fixed blocks).
#include <cstddef>
#include <vector>

#include "brdf/brdf_table.h"
#include "formats/rgl_bsdf.h"

namespace matlas {

struct RglSampleFitOptions {
  /// CG iterations (0: keep the point samples); half as many again when samples went below 0.
  int iterations = 40;
  /// Also fit the table's smooth lookup where eight measured bins meet (between the centres).
  bool corners = true;
  /// Weight of |samples - point samples|^2 in the objective, relative to the mean diagonal of the
  /// normal matrix: samples few observations reach stay near the table's values at their points.
  /// Weight of rows for the file's directional albedo at every elevation and midway between, to
  /// 85 deg (0: none), relative to the points' sum of squares; their quadrature's resolution.
  double albedo_weight = 0.3;
  int albedo_resolution = 180;
  double damping = 0.05;  // docs/EXPORT.md: at 0.01-0.2 the 83 materials' figures move a little
};

struct RglSampleFitReport {
  /// Points fitted: bin centres and corners (measured in every channel, both directions up).
  std::size_t observations = 0;
  std::size_t albedo_rows = 0;   ///< view elevations whose directional albedo is fitted
  int iterations = 0;
  /// The fitted objective relative to the table's, sqrt(sum (c (f_file - f_table))^2 / sum (c
  /// f_table)^2) at the bin centres, channels summed, before clipping: with the point samples
  /// and after the fit.
  double relative_rms_before = 0, relative_rms_after = 0;
  std::size_t clipped = 0;  ///< fitted samples below 0, written as 0
};

/// Refines `rgb`, the file's reflectance samples laid out as [theta_i][channel][y][x] (the
/// reflectance field of an isotropic RGB file, the same samples `file` holds), towards `table`.
/// `file` supplies the lookups (reflectance_lookup), so the fit sees the samples exactly as a
/// reader does.
RglSampleFitReport fit_rgl_samples(const RglBsdf& file, const BrdfTable& table, std::vector<float>& rgb,
                                   const RglSampleFitOptions& options = {});

}  // namespace matlas
