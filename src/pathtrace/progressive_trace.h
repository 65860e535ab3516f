#pragma once
// ProgressiveTrace: the GI image of one map point refined pass after pass while the user rests on
// it (the scene view's refinement, docs/GI.md): a render::Refinement (render/refinement.h, as
// previews refine) whose passes are independent trace()s of the point's own material (a bank of
// one, the model's material at the point: the full image I = P + N z + I2 of m(x), no interpolated
// I2), each with its own seed, none of them the basis's, and whose error is measured over the
// whole image. Nothing of the basis (other sampling, interpolated I2) is mixed in. Its mean can be
// denoised from its two halves, region by region (the object each pixel sees first).
#include <cstdint>
#include <memory>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"
#include "pathtrace/tracer.h"
#include "render/adaptive_sampling.h"
#include "render/denoise.h"
#include "render/refinement.h"
#include "pathtrace/world.h"

namespace matlas::pathtrace {

struct ProgressiveTraceSettings {
  /// Size, depth and density of every pass; `spp` is the first pass's samples, `seed` the seed
  /// the pass seeds derive from.
  TraceSettings trace;
  /// A GI pass stops only at a row, so its length (max_pass_spp) bounds how late a cancel lands.
  render::RefinementLimits limits{.target_error = 0.01, .min_converged_spp = 64, .max_spp = 4096, .max_pass_spp = 64};
  /// Adaptive sampling (render/adaptive_sampling.h), off by default: the trial (the first pass
  /// after the first with at least min_trial_spp samples) traces two independent halves, gives
  /// each pixel a share of the later passes' samples from their difference, and the refinement
  /// restarts from a pass with those shares (the halves that chose them are dropped: the mean
  /// stays unbiased). The built-in scenes' noise is spread over the walls and the floor (light
  /// found by paths, not one bright edge): at 30 s it gains nothing there, and the few-sample
  /// trial leaves the first seconds speckled (docs/GI.md).
  render::AdaptiveSampling adaptive{.enabled = false};
  /// Throws matlas::Error for invalid limits (render::RefinementLimits::validate) and whatever
  /// TraceSettings::validate and render::AdaptiveSampling::validate throw.
  void validate() const;
};

/// The denoiser's settings for the scene view (render/denoise.h): stronger than the previews'
/// (k = 1 on patches of 3 x 3 within 9 x 9 windows: walls and floors are smooth where previews
/// have highlights), from a sweep against a 4096-spp reference of the floor scene (docs/GI.md,
/// "The view at rest: measurements").
inline render::DenoiseSettings scene_denoise_settings() {
  render::DenoiseSettings s;
  s.search_radius = 4;
  s.patch_radius = 1;
  s.strength = 1.0;
  return s;
}

class ProgressiveTrace {
public:
  /// The world and the bank (one material) must outlive the refinement (shared pointers).
  ProgressiveTrace(std::shared_ptr<const World> world, std::shared_ptr<const render::MaterialBank> bank,
                   ProgressiveTraceSettings settings);

  /// Adds passes for about `seconds` (render::Refinement::refine).
  render::RefinementState refine(double seconds, ProgressSink& progress = null_progress()) {
    return refinement_.refine(seconds, progress);
  }
  render::RefinementState state() const { return refinement_.state(); }
  /// The mean of every pass so far (black before the first).
  Image image() const { return refinement_.image(); }
  /// The mean denoised from its two halves (render/denoise.h: biased, consistent), with the noise
  /// it estimates left; each half's lone fireflies are removed first (render/firefly_filter.h),
  /// pixels are averaged only with pixels that see the same object first, and pixels whose
  /// footprint spans two objects (silhouettes, the floor's horizon) are left as they are. Before
  /// both halves have samples: image() and an infinite error.
  render::DenoiseResult denoised(const render::DenoiseSettings& settings = scene_denoise_settings()) const;
  /// Per pixel, what its footprint sees first: 1 + the object's index, 255 the environment (or
  /// objects from 254 on), 0 a footprint over two of them (2 x 2 rays per pixel).
  const std::vector<std::uint8_t>& regions() const { return region_; }
  /// The seed of pass k (never the trace settings' own seed, which the basis uses).
  static std::uint64_t pass_seed(std::uint64_t seed, int pass);
  /// Per pixel, its share of a pass's samples since the trial (null before it or without
  /// adaptive sampling). Between refine() calls (the refining thread sets it).
  std::shared_ptr<const std::vector<double>> pixel_samples() const { return pixel_samples_; }

private:
  /// One pass (its settings' spp and seed): the full image of the point's material; the second
  /// pass is adaptive sampling's trial.
  Image pass(TraceSettings s, ProgressSink& progress);

  std::shared_ptr<const World> world_;
  std::shared_ptr<const render::MaterialBank> bank_;
  ProgressiveTraceSettings settings_;
  int passes_ = 0;  ///< passes traced before the trial
  std::shared_ptr<const std::vector<double>> pixel_samples_;
  std::vector<std::uint8_t> region_;  ///< regions(): for the denoiser
  render::Refinement refinement_;
};

}  // namespace matlas::pathtrace
