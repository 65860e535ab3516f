#pragma once
// The coefficient file of a database or model (safetensors, readable from numpy), laid out for a
// fragment shader (docs/REALTIME.md):
//
//   coefficients  F32 or F16 [n, T, S, 3]  lambda of material i at theta_o sample t, coefficient
//                                          j = lm_index(l, k), RGB, then (j = K + i) the weight of
//                                          lobe i (S = K + M): one material is a T x S RGB
//                                          texture (row t = theta_o sample)
//   mean          same dtype [T, S, 3]     (models only) the coefficients of the model's mean
//                                          table: a map point with weights w has
//                                          mean + sum_i w_i (coefficients_i - mean)
//   alpha         F32 [K]                  alpha_{l,k}: d = sin(alpha) x + cos(alpha) n
//   band          I32 [K]                  l of coefficient j
//   theta_o       F32 [T]                  (t + 0.5) (pi/2) / T
// metadata: format "matlas-zonal", version "2", bands, theta_o_count, theta_rows, phi_columns,
// lobes (JSON array of the lobes' sharpnesses kappa_i, zonal/lobes.h; may be empty),
// ring_floor (only when the bands were weighted by zonal::RingLimiter: its floor), names (JSON array), storage ("f32"/"f16"), storage_error (the largest |stored - exact| over
// the largest |coefficient|, measured when written), and source_key when the set has one.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "formats/safetensors.h"
#include "zonal/coefficients.h"
#include "zonal/projection.h"

namespace matlas::zonal {

struct CoefficientSet {
  ProjectionSettings settings;
  std::vector<std::string> names;
  std::vector<ZonalCoefficients> materials;
  std::optional<ZonalCoefficients> mean;
  /// What the set was computed from (a cache's key, atlas/zonal_cache.h); empty if not known.
  std::string source_key;
};

/// Writes the set (AtomicFile) with F32 or F16 storage; returns the measured storage error.
double write_coefficients(const std::filesystem::path& path, const CoefficientSet& set, DType storage);

/// Reads a coefficient file (version 2, or version 1: written before the lobes, read as a set
/// without lobes, which it is); matlas::Error naming the file and the problem for anything else,
/// a newer version included.
CoefficientSet read_coefficients(const std::filesystem::path& path);

}  // namespace matlas::zonal
