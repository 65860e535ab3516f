#pragma once
// The renderer: direct lighting of one object by an environment map and directional lights,
// with shadows, for tabulated (or any) BRDFs.
//
// Estimator. Per pixel, `spp` primary rays (jittered in the pixel). At the object, one direction
// wi is drawn from one strategy of a FIXED mixture (render/sampling_mixture.h: environment importance
// sampling, cosine lobe, GGX lobes of given widths around the view's mirror direction, a tabulated
// half-vector lobe), the strategies sharing the pixel's samples in fixed counts with stratified
// numbers (render/pixel_sampler.h; RenderSettings::sampler), and weighted by the balance-heuristic
// mixture density; every directional light adds one shadow ray. The pixel is
//
//     I = C + sum_s W_s * f(wi_s, wo_s)           (W_s: RGB, independent of f)
//
// where C collects everything that does not see the object's BRDF (background, ground). The
// directions and weights depend only on the scene, the settings and the seed, never on the
// material, so I is LINEAR in f and renders of different materials share their samples exactly:
// the image of a manifold point is the same combination of images as its BRDF is of tables.
#include <cstdint>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"
#include "render/material.h"
#include "render/sampling_mixture.h"
#include "render/scene.h"

namespace matlas::render {

/// How a pixel's samples draw their random numbers (both material-independent).
enum class Sampler {
  /// Each sample draws its jitter, strategy and direction from its own hashed stream, the strategy
  /// at random with the mixture's probabilities (one-sample mixture).
  independent,
  /// render/pixel_sampler.h: fixed sample counts per strategy (multi-sample balance heuristic),
  /// each strategy's jitters and directions from Owen-scrambled Sobol points of the pixel.
  stratified,
  /// As stratified, and every camera sample ALSO takes one environment sample: the camera samples
  /// share the lobe strategies (cosine, GGX, tabulated) in fixed counts, and each adds a light
  /// sample, both taps weighted by the multi-sample balance heuristic over all strategies
  /// (environment count = spp). Two taps and two shadow rays per camera sample.
  light_and_lobe,
};

struct RenderSettings {
  int width = 512;
  int height = 512;
  int spp = 64;             ///< samples (primary rays, each with one environment sample) per pixel
  std::uint64_t seed = 1;
  /// The sampling strategies at the object: fixed, material-independent (a model's renders use
  /// the mixture fitted to its database, atlas/sampling_fit.h).
  SamplingMixture mixture = SamplingMixture::preview_default();
  Sampler sampler = Sampler::stratified;
  /// Weighs the environment strategy against the lobe strategies (taken together as one mixture
  /// technique) with the power heuristic (exponent 2) instead of the balance heuristic; both are
  /// material-independent. Stratified samplers only.
  bool power_heuristic = false;

  /// Throws matlas::Error for non-positive sizes or spp, or an all-zero mixture.
  void validate() const;
};

/// Counters of one render.
struct RenderStats {
  std::uint64_t camera_samples = 0;  ///< primary rays
  std::uint64_t object_samples = 0;  ///< BRDF evaluations (taps)
  double seconds = 0;
};

/// Renders one material. Deterministic for a seed (independent of the thread count).
Image render(const Scene& scene, const Material& material, const RenderSettings& settings,
             ProgressSink& progress = null_progress(), RenderStats* stats = nullptr);

/// Renders every material of a bank with the same samples: images[k] for material k. Equal to
/// calling render() for each material (to rounding), at a fraction of the cost.
std::vector<Image> render_bank(const Scene& scene, const MaterialBank& bank, const RenderSettings& settings,
                               ProgressSink& progress = null_progress(), RenderStats* stats = nullptr);

/// Per pixel, the fraction of primary rays that hit the object (0 = background only).
std::vector<float> object_coverage(const Scene& scene, const RenderSettings& settings);

}  // namespace matlas::render
