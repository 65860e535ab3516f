#pragma once
// The transform of the data used to place the latent points (the interpolation itself always
// stays linear in the original data), and its application to the kept columns of a block.
#include <cstddef>
#include <span>
#include <string>

#include "manifold/column_blocks.h"
#include "manifold/kept_runs.h"

namespace matlas {

/// Each value f at bin b becomes
///   g(f) * (cosine_weighted ? cos(theta_i) cos(theta_o) at the bin centre : 1)
/// with g the identity, cube root, or log(1 + f / 0.01).
struct LayoutTransform {
  enum class Map { linear, cube_root, log } map = Map::linear;
  bool cosine_weighted = false;

  std::string to_string() const;  ///< e.g. "linear", "cosine-cbrt", "log"
  /// Parses "linear", "cbrt", "log", optionally prefixed "cosine-"; throws matlas::Error.
  static LayoutTransform parse(const std::string& name);
  bool is_identity() const { return map == Map::linear && !cosine_weighted; }
};

/// The layout's copy of a block's kept columns beside their centred copy, each value read once:
/// centred[i, run.out + t] = values[i, run.first + t] - mean[run.first + t] (double), and
/// transformed[i, run.out + t] = g(values[i, run.first + t]) * (cosine_weighted ?
/// cosine[run.first + t] : 1), minus that column's mean over the rows (summed in double, in row
/// order). Any map; the pass calls it for the non-linear ones, which apply to the raw values (a
/// linear map with a per-column factor commutes with centring: centre_kept does it with one sum
/// less). Both outputs row-major with row stride ld.
/// Single precision for the layout's copy (about 1e-7 relative): it only places the latent
/// points, through a Gram matrix accumulated in double from single-precision slices
/// (manifold/gram.h).
void centre_and_transform_kept(const BlockMatrix& values, std::span<const KeptRun> runs, const double* mean,
                               double* centred, const LayoutTransform& layout, const float* cosine,
                               float* transformed, std::size_t ld);

}  // namespace matlas
