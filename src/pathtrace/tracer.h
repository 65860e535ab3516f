#pragma once
// The path tracer (docs/GI.md). Unidirectional paths from the camera with next-event estimation
// (environment and area lights, one sample each per vertex) combined with the surfaces' sampling
// densities by multiple importance sampling (power heuristic), and Russian roulette. A vertex that
// sees a glossy plane draws its next direction from a mixture of its own density and the
// environment's mirror image in the plane (pathtrace/mirrored_environment.h: the caustics of a
// glossy floor). Directional
// lights (delta lights) are connected at every vertex, each by one shadow ray, without MIS. With
// max_depth = 1 the image is the direct lighting alone: what the previews' estimator computes
// (render/render.h) for the same scene (pathtrace/preview_scene.h).
//
// The measured object is sampled with a FixedDensity and its BRDF enters a path only as a
// factor f(bin); nothing else on the path (directions, weights, roulette) depends on it. So each
// contribution is C * prod_j f(bin_j) over the path's vertices on the measured object, with C
// independent of the material, and the image splits as
//
//     I = P + N z + I2
//
// P: contributions touching the object zero times; N z: exactly once (linear in the table z);
// I2: twice or more. trace() computes P once and N z_k and I2_k for every material k of a bank
// with the same paths and random numbers (a hash of seed, pixel, sample, dimension: the same for
// every thread count).
#include <cstdint>
#include <memory>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"
#include "pathtrace/surface.h"
#include "pathtrace/world.h"
#include "render/material.h"

namespace matlas::pathtrace {

struct TraceSettings {
  int width = 256;
  int height = 256;
  int spp = 64;
  std::uint64_t seed = 1;
  int max_depth = 8;       ///< scattering vertices per path (1: direct lighting only)
  int roulette_depth = 3;  ///< Russian roulette from this many vertices on
  FixedDensity density = default_fixed_density();  ///< the measured object's sampling density
  /// The probability of drawing a vertex's next direction towards the environment's mirror image
  /// in a glossy plane of the scene (pathtrace/mirrored_environment.h), in [0, 1); used only at
  /// vertices that see such a plane (0 elsewhere). 0: every vertex samples its own density.
  double mirror_probability = 0.25;
  /// Per pixel (row-major), its share of the samples: pixel p takes max(1, round(spp x share))
  /// (adaptive sampling, render/adaptive_sampling.h; the same for every material of a bank, so
  /// the split stays exact). Null: spp everywhere.
  std::shared_ptr<const std::vector<double>> pixel_samples;
  /// Throws matlas::Error for non-positive sizes, spp or depth, a bad density, a mirror
  /// probability outside [0, 1), or pixel_samples of another size than the image or with a share
  /// that is not positive and finite.
  void validate() const;
};

struct TraceImages {
  Image p;                    ///< paths that never touch the measured object
  std::vector<Image> once;    ///< N z_k: paths touching it exactly once, per material
  std::vector<Image> more;    ///< I2_k: twice or more, per material
  /// P + N z_k (+ I2_k): the I1 and the full image of material k.
  Image i1(int k) const;
  Image full(int k) const;
};

/// Traces the scene with every material of `bank` on the measured object (bank may be null when
/// the scene has none; then only p is filled).
TraceImages trace(const World& world, const render::MaterialBank* bank, const TraceSettings& settings,
                  ProgressSink& progress = null_progress());

}  // namespace matlas::pathtrace
