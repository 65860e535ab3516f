#pragma once
// The data of the browser's real-time viewer (docs/REALTIME.md, "The browser viewer"), laid out
// as its textures want them:
//
// - coefficients: float32, the mean's [T, S, 3] (zeros for a set without mean) followed by each
//   material's [T, S, 3], in the order of the set: n + 1 blocks of T * S * 3 values (S = K + M:
//   the K rotated-ZH coefficients, then the M lobe weights, zonal/coefficients.h);
// - environment: the L + 1 band maps E_l on one octahedral grid (y up): a direction d maps to
//   p = (d_x, d_z) / (|d_x| + |d_y| + |d_z|), folded for d_y < 0 to (1 - |p_z|, 1 - |p_x|) with
//   p's signs; the N x N texels of [-1, 1]^2 sit at p = 2 (i + 1/2) / N - 1, surrounded by a
//   border of one texel that continues the map across its edges (p_x beyond +-1 is p_x mirrored
//   at the edge with p_z negated, and likewise for p_z), so that hardware bilinear filtering of a
//   texture array (clamp) is continuous everywhere and needs no trigonometry per lookup. float32
//   [L + 1, N + 2, N + 2, 3]. Every texel is PrefilteredEnvironment::lookup (the CPU
//   reference's own bilinear read of band l's lat-long map) at its direction.
#include <vector>

#include "zonal/coefficient_file.h"
#include "zonal/prefilter.h"

namespace matlas::zonal {

/// The mean's block, then each material's, as float32.
std::vector<float> pack_coefficients(const CoefficientSet& set);

struct EnvironmentAtlas {
  int bands = 0;   ///< L: L + 1 layers
  int width = 0;   ///< N + 2 (N texels of [-1, 1] and the border on each side)
  int height = 0;  ///< N + 2
  std::vector<float> values;  ///< [layer][row][column][channel]
};

/// N = 12 (L + 1): about as many texels per layer as band L's lat-long map has; the octahedral
/// grid's spacing varies less (at most by a factor of about 1.4).
int octahedral_side(int bands);

/// The unit direction of octahedral coordinates p (any p: outside [-1, 1]^2 it is first mirrored
/// back across the edges, as the border texels are).
Vec3 octahedral_direction(double px, double pz);

/// Every band of `env` on the octahedral grid of side `side` (0: octahedral_side(L)).
EnvironmentAtlas pack_environment(const PrefilteredEnvironment& env, int side = 0);

/// The detail layers, on a finer octahedral grid of side `side` (same layout and border): the M
/// lobe maps of `env` (PrefilteredEnvironment::lobe_lookup), then the background, `raw`'s
/// Environment::eval_smooth (what the renderer shows where a ray misses the object). `bands`
/// holds M: M + 1 layers. The viewer's default side is kDetailSide.
EnvironmentAtlas pack_detail(const PrefilteredEnvironment& env, const render::Environment& raw, int side);
inline constexpr int kDetailSide = 320;

}  // namespace matlas::zonal
