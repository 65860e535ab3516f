#pragma once
// The interpolation modes of a model: how a latent point becomes a combination of the inputs.
#include <string>

namespace matlas {

/// How a latent point becomes a combination of the inputs (docs/GP.md, "Interpolation modes").
enum class Interpolation {
  /// The paper's GP: m(x) = mean + sum_i w_i(x) (z_i - mean), weights of any sign.
  gp,
  /// The GP's affine combination projected onto the simplex in the metric of the placement Gram
  /// (gp/convex_weights.h): non-negative weights summing to 1, so every table is a convex
  /// combination of the inputs (no negative value, reciprocal, albedo at most the inputs' largest).
  convex,
};
const char* to_string(Interpolation mode);
/// Accepts "gp" and "convex"; throws matlas::Error naming the valid choices otherwise.
Interpolation interpolation_from_string(const std::string& name);

}  // namespace matlas
