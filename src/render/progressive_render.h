#pragma once
// ProgressiveRender: one material's image refined pass after pass until it converges, the way a
// material editor's preview keeps improving while the pointer rests.
//
// Every pass is an independent render (render/render.h) with its own seed: each is an unbiased
// estimate of the same image, so the passes are averaged weighted by their samples per pixel and
// nothing of different sampling is mixed without its weight. The passes go alternately into two
// halves A and B (the one with fewer samples takes the next), which gives the error of the mean
// without a reference: with a and b samples, per pixel
//
//     Var(mean) = Var(A - B) a b / (a + b)^2,   Var(A - B) estimated by (A - B)^2,
//
// summed over the pixels that see only the object; `relative_error` is the root of that sum over
// the sum of the squared mean: the RMS error of the image inside the object relative to its RMS
// value there (the normalisation of docs/RENDERING.md's noise figures; relative to the plain mean,
// a small bright highlight, which tone mapping saturates, would dominate the figure). Pass sizes are powers of two (the stratified
// sampler's points stay balanced) chosen from the time the passes so far took, so that one call
// of refine() stays within its time.
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"
#include "render/denoise.h"
#include "render/material.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas::render {

struct ProgressiveSettings {
  /// Size, sampler and sampling mixture of every pass; `spp` is the first pass's samples and
  /// `seed` the first pass's seed (pass k takes a seed derived from it and k).
  RenderSettings render;
  /// Refinement stops once the estimated relative error is at most this (and at least
  /// `min_converged_spp` samples are in) or `max_spp` samples are in.
  double target_error = 0.004;
  int min_converged_spp = 128;
  int max_spp = 16384;
  /// Samples per pixel of one pass at most (a pass cannot be interrupted but by the progress
  /// sink, so its length bounds how late a cancelled refinement stops).
  int max_pass_spp = 256;
  /// Throws matlas::Error for a non-positive target, min_converged_spp or pass size, or
  /// max_spp below the first pass; and whatever RenderSettings::validate throws.
  void validate() const;
};

/// The samples of a refinement's next pass (previews here, the scene view in
/// pathtrace/progressive_trace.h): the first pass's `first_spp` while nothing is in; then what fits
/// `seconds_left` at the rate so far (`spp_in` samples in `seconds_in`), a power of two, at least
/// the first pass's, at most doubling what is in, at most `max_pass_spp` and what `max_spp`
/// leaves. 0 when it is not the call's first pass (`first` false) and no such pass fits the time.
int next_pass_spp(int first_spp, int max_pass_spp, int max_spp, int spp_in, double seconds_in, double seconds_left,
                  bool first);

/// Where a refinement stands.
struct ProgressiveState {
  int spp = 0;          ///< samples per pixel averaged so far (0: nothing rendered yet)
  int passes = 0;
  double relative_error = std::numeric_limits<double>::infinity();  ///< estimated; inf before two passes
  double seconds = 0;   ///< render time spent on it so far
  bool converged = false;
};

class ProgressiveRender {
public:
  /// The scene and the material must stay alive as long as the refinement (the shared pointers
  /// keep them). Throws matlas::Error for invalid settings.
  ProgressiveRender(std::shared_ptr<const Scene> scene, std::shared_ptr<const Material> material,
                    ProgressiveSettings settings);

  /// Adds passes for about `seconds` (at least one pass, none once converged). Safe to call from
  /// several threads (one refines at a time). If the progress sink throws (cancellation), the
  /// pass under way is dropped and the state is what it was before it.
  ProgressiveState refine(double seconds, ProgressSink& progress = null_progress());

  ProgressiveState state() const;
  /// The mean of every pass so far (a black image before the first).
  Image image() const;
  /// The mean denoised from its two halves (render/denoise.h: biased, consistent), with the noise
  /// it estimates left; the object, the background and the partially covered silhouette (left as
  /// it is) are not mixed. Before both halves have samples: image() and an infinite error.
  DenoiseResult denoised(const DenoiseSettings& settings = {}) const;
  /// Per pixel, whether it sees only the object (where the error is measured).
  const std::vector<bool>& object_pixels() const { return object_; }

private:
  Image mean_locked() const;  ///< image(), with state_mutex_ held
  void add_pass(const Image& pass, int spp, double seconds);
  void update_error();

  std::shared_ptr<const Scene> scene_;
  std::shared_ptr<const Material> material_;
  ProgressiveSettings settings_;
  std::vector<bool> object_;
  std::vector<std::uint8_t> region_;  ///< for the denoiser: 1 object only, 2 no object, 0 silhouette
  std::mutex refining_;         ///< held by the thread that renders a pass
  mutable std::mutex state_mutex_;  ///< guards the sums and the state
  std::vector<double> sum_[2];  ///< per half: the sum of spp x pass image
  int half_spp_[2] = {0, 0};
  ProgressiveState state_;
};

}  // namespace matlas::render
