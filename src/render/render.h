#pragma once
// The renderer: direct lighting of one object by an environment map and directional lights,
// with shadows, for tabulated (or any) BRDFs.
//
// Estimator. Per pixel, about `spp` primary rays (jittered in the pixel; more where the pixel sees
// the object at grazing angles, fewer elsewhere, the image's mean being spp:
// RenderSettings::grazing_samples). At the object, every camera
// sample takes one environment sample (next-event estimation) and one direction from a lobe
// strategy of a FIXED mixture (render/sampling_mixture.h: cosine lobe, GGX lobes of given widths
// around the view's mirror direction, a tabulated half-vector lobe), the lobe strategies sharing
// the pixel's samples in fixed counts with stratified numbers (render/pixel_sampler.h;
// RenderSettings::sampler), both taps weighted by the multi-sample balance heuristic; every
// directional light adds one shadow ray. The pixel is
//
//     I = C + sum_s W_s * f(wi_s, wo_s)           (W_s: RGB, independent of f)
//
// where C collects everything that does not see the object's BRDF (background, ground). The
// directions and weights depend only on the scene, the settings and the seed, never on the
// material, so I is LINEAR in f and renders of different materials share their samples exactly:
// the image of a manifold point is the same combination of images as its BRDF is of tables.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"
#include "render/control_grid.h"
#include "render/material.h"
#include "render/sampling_mixture.h"
#include "render/scene.h"

namespace matlas::render {

/// How a pixel's samples draw their random numbers (all material-independent).
enum class Sampler {
  /// Each sample draws its jitter, strategy and direction from its own hashed stream, the strategy
  /// at random with the mixture's probabilities (one-sample mixture).
  independent,
  /// render/pixel_sampler.h: fixed sample counts per strategy (multi-sample balance heuristic),
  /// each strategy's jitters and directions from Owen-scrambled Sobol points of the pixel.
  stratified,
  /// The default. As stratified, and every camera sample ALSO takes one environment sample, the
  /// way a path tracer's sample takes a light sample and a material sample: the camera samples
  /// share the lobe strategies (cosine, GGX, tabulated) in fixed counts, and each adds a light
  /// sample, both taps weighted by the multi-sample balance heuristic over all strategies
  /// (environment count = spp; the mixture's environment probability is not used). Two taps and
  /// two shadow rays per camera sample: 1.6-1.9x the time of `stratified` at equal spp, for
  /// 1.3-1.8x less noise on the database's glossy materials (docs/RENDERING.md "Noise").
  light_and_lobe,
};

struct RenderSettings {
  int width = 512;
  int height = 512;
  int spp = 64;             ///< samples (primary rays; light_and_lobe: each with an environment sample) per pixel
  std::uint64_t seed = 1;
  /// The sampling strategies at the object: fixed, material-independent (a model's renders use
  /// the mixture fitted to its database, atlas/sampling_fit.h).
  SamplingMixture mixture = SamplingMixture::preview_default();
  Sampler sampler = Sampler::light_and_lobe;
  /// Weighs the environment strategy against the lobe strategies (taken together as one mixture
  /// technique) with the power heuristic (exponent 2) instead of the balance heuristic; both are
  /// material-independent. Stratified samplers only.
  bool power_heuristic = false;
  /// Camera samples per pixel follow the view angle at the pixel's centre, which does not depend
  /// on the material: where it sees the object at cos(theta_o) < 0.5 a pixel covers 1 / cos(theta_o)
  /// times the surface and, near the silhouette, reflects a wide range of directions (every
  /// glossy material turns mirror-like at grazing angles), so it takes samples in proportion to
  /// 1 / cos(theta_o), at most this factor times a frontal pixel's; the counts are then scaled so
  /// that the image's mean stays spp (the same number of camera samples in all). 1: every pixel
  /// takes spp.
  double grazing_samples = 4.0;
  /// Per pixel (row-major), its share of the camera samples, replacing the grazing rule: pixel p
  /// takes max(1, round(spp x pixel_samples[p])) (a caller that wants the image's mean to stay spp
  /// gives shares of mean 1). Adaptive sampling (render/adaptive_sampling.h) sets it from the noise
  /// of earlier passes; which pixel takes how many samples does not depend on the material of this
  /// render, so a basis stays linear. Null: grazing_samples' rule.
  std::shared_ptr<const std::vector<double>> pixel_samples;

  /// Throws matlas::Error for non-positive sizes or spp, an all-zero mixture, grazing_samples
  /// outside [1, 64], (light_and_lobe) a mixture without a lobe strategy, or pixel_samples of
  /// another size than the image or with a share that is not positive and finite.
  void validate() const;
};

/// Counters of one render.
struct RenderStats {
  std::uint64_t camera_samples = 0;  ///< primary rays (about width x height x spp)
  std::uint64_t object_samples = 0;  ///< BRDF evaluations (taps)
  double seconds = 0;
};


/// A control variate for render(): the function, its grid (render/control_grid.h; none: every camera
/// sample evaluates the smooth integral), and where to put the plain estimate of the same
/// samples (the image without the control variate, for a caller that chooses between the two).
struct Control {
  const ControlVariate* variate = nullptr;
  const ControlGrid* grid = nullptr;
  Image* plain = nullptr;
};

/// Renders one material. Deterministic for a seed (independent of the thread count). With a
/// control variate (render/control_variate.h) the object's pixels estimate the same image with
/// the variance of the material's difference from it.
Image render(const Scene& scene, const Material& material, const RenderSettings& settings,
             ProgressSink& progress = null_progress(), RenderStats* stats = nullptr, const Control& control = {});

/// The rows of an image that a render computes: every `parts`-th row from row `part`, so that a
/// render split across processes gives each a share of sky, object and ground alike (a band of
/// rows would give one process the sky and another the object). The default is every row.
struct RowShare {
  int part = 0, parts = 1;
  /// The number of rows of an image of `height` rows in this share.
  int rows(int height) const { return height > part ? (height - part + parts - 1) / parts : 0; }
  /// The image row of the share's row j.
  int row(int j) const { return part + j * parts; }
};

/// Renders every material of a bank with the same samples: images[k] for material k. Equal to
/// calling render() for each material (to rounding), at a fraction of the cost. With a share of
/// the rows, images of share.rows(height) rows: row j is image row share.row(j), the same pixels
/// as the whole render's (every pixel's samples depend on the pixel only).
std::vector<Image> render_bank(const Scene& scene, const MaterialBank& bank, const RenderSettings& settings,
                               ProgressSink& progress = null_progress(), RenderStats* stats = nullptr,
                               RowShare share = {});

/// Per pixel (row-major), the number of camera samples a render takes (spp everywhere unless
/// RenderSettings::grazing_samples > 1 or pixel_samples is set).
std::vector<int> sample_counts(const Scene& scene, const RenderSettings& settings);

/// Per pixel, the fraction of primary rays that hit the object (0 = background only).
std::vector<float> object_coverage(const Scene& scene, const RenderSettings& settings);

}  // namespace matlas::render
