#pragma once
// ProgressiveRender: one material's preview refined pass after pass until it converges, the way a
// material editor's preview keeps improving while the pointer rests: a render::Refinement
// (render/refinement.h: passes averaged in two halves, the error of the mean estimated from them)
// whose passes are independent renders (render/render.h), whose error is measured over the pixels
// that see only the object, and whose mean can be denoised from its two halves.
#include <atomic>
#include <functional>
#include <memory>
#include <vector>

#include "core/progress.h"
#include "render/adaptive_sampling.h"
#include "formats/image_io.h"
#include "render/denoise.h"
#include "render/material.h"
#include "render/refinement.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas::render {

struct ProgressiveSettings {
  /// Size, sampler and sampling mixture of every pass; `spp` is the first pass's samples and
  /// `seed` the first pass's seed (pass k takes a seed derived from it and k).
  RenderSettings render;
  RefinementLimits limits{.target_error = 0.004, .min_converged_spp = 128, .max_spp = 16384, .max_pass_spp = 256};
  /// Makes a control variate (render/control_variate.h; none: the plain estimator; it may return
  /// null while one is not ready, and is asked again at the next pass). The first pass is plain
  /// (the first image as fast as without one); the next makes the control variate and its grid,
  /// renders both estimates in two independent halves and keeps the one with less noise per unit
  /// of time (halves_noise squared times the seconds per sample of its passes): with the control variate
  /// the refinement restarts from that pass (Refinement::restart), else it goes on plain
  /// (docs/RENDERING.md "Control variate").
  std::function<std::shared_ptr<const ControlVariate>()> control_variate = nullptr;
  /// Adaptive sampling (render/adaptive_sampling.h): the trial (the first pass after the first
  /// with at least min_trial_spp samples; with the control variate's trial when that is due)
  /// renders two independent halves, gives each pixel a share of the later passes' samples from
  /// the chosen estimator's noise there, and the refinement restarts from a pass with those shares
  /// (Refinement::restart: the passes that chose them are dropped, the mean stays unbiased).
  AdaptiveSampling adaptive;
  /// How the image is shown: adaptive sampling weighs the error as shown besides the linear one
  /// (render::linear_and_shown_weights).
  ToneMap shown{ToneMap::Curve::aces, 0.0};
  /// Throws matlas::Error for invalid limits (RefinementLimits::validate) and whatever
  /// RenderSettings::validate and AdaptiveSampling::validate throw.
  void validate() const;
};

/// The relative noise of two independent estimates a, b of one image where `object` is set:
/// RMS(a - b) / RMS((a + b) / 2), the image's own structure cancelling.
double halves_noise(const Image& a, const Image& b, const std::vector<bool>& object);

class ProgressiveRender {
public:
  /// The scene and the material must stay alive as long as the refinement (the shared pointers
  /// keep them). Throws matlas::Error for invalid settings.
  ProgressiveRender(std::shared_ptr<const Scene> scene, std::shared_ptr<const Material> material,
                    ProgressiveSettings settings);

  /// Adds passes for about `seconds` (Refinement::refine).
  RefinementState refine(double seconds, ProgressSink& progress = null_progress()) {
    return refinement_.refine(seconds, progress);
  }
  RefinementState state() const { return refinement_.state(); }
  /// The mean of every pass so far (a black image before the first).
  Image image() const { return refinement_.image(); }
  /// The mean denoised from its two halves (render/denoise.h: biased, consistent), with the noise
  /// it estimates left; the object, the background and the partially covered silhouette (left as
  /// it is) are not mixed. Before both halves have samples: image() and an infinite error.
  DenoiseResult denoised(const DenoiseSettings& settings = {}) const;
  /// With a control variate: whether the passes use it (false before the first pass or without one).
  bool controlled() const { return control_ == ControlChoice::controlled; }
  /// Per pixel, its share of a pass's samples since the last restart (null: the grazing rule).
  /// Between refine() calls (the refining thread sets it).
  std::shared_ptr<const std::vector<double>> pixel_samples() const { return pixel_samples_; }
  /// Per pixel, whether it sees only the object (where the error is measured).
  const std::vector<bool>& object_pixels() const { return object_; }

private:
  ProgressiveRender(std::shared_ptr<const Scene> scene, std::shared_ptr<const Material> material,
                    const ProgressiveSettings& settings, const std::vector<float>& coverage);
  /// One pass of the refinement (its settings' spp and seed): plain or with the control variate.
  Image pass(RenderSettings s, ProgressSink& progress);
  /// The settings validated, then the coverage of the object per pixel.
  static std::vector<float> checked_coverage(const Scene* scene, const ProgressiveSettings& settings);

  std::shared_ptr<const Scene> scene_;
  std::shared_ptr<const Material> material_;
  ProgressiveSettings settings_;
  std::vector<bool> object_;
  std::vector<std::uint8_t> region_;  ///< for the denoiser: 1 object only, 2 no object, 0 silhouette
  std::shared_ptr<const ControlVariate> control_variate_;  ///< made by the second pass
  ControlGrid control_grid_;          ///< with a control variate: its smooth integral, once for every pass
  /// With a control variate: whether the passes use it, chosen by the first pass.
  enum class ControlChoice { undecided, controlled, plain };
  std::atomic<ControlChoice> control_ = ControlChoice::undecided;
  double plain_seconds_per_spp_ = 0;  ///< of the last plain pass before the choice
  int plain_passes_ = 0;              ///< timed plain passes (before the choices)
  std::shared_ptr<const std::vector<double>> pixel_samples_;  ///< chosen by the last trial
  Refinement refinement_;
};

}  // namespace matlas::render
