#pragma once
// The data of the browser's real-time viewer (docs/REALTIME.md, "The browser viewer"), laid out
// as its textures want them:
//
// - coefficients: float32, the mean's [T, K, 3] (zeros for a set without mean) followed by each
//   material's [T, K, 3], in the order of the set: n + 1 blocks of T * K * 3 values;
// - environment: the L + 1 band maps E_l resampled onto one lat-long grid (that of band L:
//   H = map_height(L) rows at theta = pi y / (H - 1), W = 2 (H - 1) columns at phi = 2 pi x / W),
//   float32 [L + 1, H, W, 3], so that one texture array with hardware bilinear filtering (repeat
//   in phi, clamp in theta) reads every band. Bands below L are read bilinearly from their own
//   maps (PrefilteredEnvironment::lookup) at the grid's points; band L is its own map.
#include <vector>

#include "zonal/coefficient_file.h"
#include "zonal/prefilter.h"

namespace matlas::zonal {

/// The mean's block, then each material's, as float32.
std::vector<float> pack_coefficients(const CoefficientSet& set);

struct EnvironmentAtlas {
  int bands = 0;   ///< L: L + 1 layers
  int width = 0;   ///< W
  int height = 0;  ///< H
  std::vector<float> values;  ///< [layer][row][column][channel]
};

/// Every band of `env` on band L's grid.
EnvironmentAtlas pack_environment(const PrefilteredEnvironment& env);

}  // namespace matlas::zonal
