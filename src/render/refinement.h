#pragma once
// Refinement: an image refined pass after pass while the user rests on it — the one bookkeeping of
// every refined image (previews in render/progressive_render.h, the scene view's GI in
// pathtrace/progressive_trace.h); the integrator is the caller's (a function rendering one pass).
//
// Every pass is an independent render with its own seed: each is an unbiased estimate of the same
// image, so the passes are averaged weighted by their samples per pixel and nothing of different
// sampling is mixed without its weight. The passes go alternately into two halves A and B (the one
// with fewer samples takes the next), which gives the error of the mean without a reference: with
// a and b samples, per pixel
//
//     Var(mean) = Var(A - B) a b / (a + b)^2,   Var(A - B) estimated by (A - B)^2,
//
// summed over the measured pixels (all, or those the caller names: a preview measures the pixels
// that see only the object); `relative_error` is the root of that sum over the sum of the squared
// mean: the RMS error of the measured image relative to its RMS value (relative to the plain mean,
// a small bright highlight, which tone mapping saturates, would dominate the figure). Pass sizes
// are powers of two (the stratified sampler's points stay balanced) chosen from the time the passes
// so far took, so that one call of refine() stays within its time.
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"

namespace matlas::render {

/// When a refinement stops and how large its passes get.
struct RefinementLimits {
  /// Converged once the estimated relative error is at most this (and at least
  /// `min_converged_spp` samples are in) or `max_spp` samples are in.
  double target_error = 0.01;
  int min_converged_spp = 64;
  int max_spp = 4096;
  /// Samples per pixel of one pass at most (a pass is interrupted only by its progress sink, so
  /// its length bounds how late a cancelled refinement stops).
  int max_pass_spp = 64;
  /// Throws matlas::Error, naming `who`, for a non-positive or non-finite target, a
  /// min_converged_spp or pass size below 1, or max_spp below `first_spp` (the first pass).
  void validate(int first_spp, const char* who) const;
};

/// Where a refinement stands.
struct RefinementState {
  int spp = 0;          ///< samples per pixel averaged so far (0: nothing rendered yet)
  int passes = 0;
  double relative_error = std::numeric_limits<double>::infinity();  ///< estimated; inf before two passes
  double seconds = 0;   ///< render time spent on it so far
  bool converged = false;
};

/// The samples of a refinement's next pass: the first pass's `first_spp` while nothing is in;
/// then what fits `seconds_left` at the rate so far (`spp_in` samples in `seconds_in`), a power of
/// two, at least the first pass's, at most doubling what is in, at most `max_pass_spp` and what
/// `max_spp` leaves. 0 when it is not the call's first pass (`first` false) and no such pass fits
/// the time.
int next_pass_spp(int first_spp, int max_pass_spp, int max_spp, int spp_in, double seconds_in, double seconds_left,
                  bool first);

/// The two halves' means and samples (for a denoiser that compares them: render/denoise.h).
struct RefinementHalves {
  Image a, b;
  double samples_a = 0, samples_b = 0;
};

class Refinement {
public:
  /// One pass of `spp` samples per pixel with `seed` (a width x height image); may throw from the
  /// progress sink (cancellation).
  using Pass = std::function<Image(int spp, std::uint64_t seed, ProgressSink& progress)>;
  /// The seed of pass k (0, 1, ...) from the refinement's own seed.
  using PassSeed = std::function<std::uint64_t(int pass)>;

  /// `measured`: per pixel, whether its error counts (empty: every pixel). Throws matlas::Error
  /// for invalid limits (naming `who`).
  Refinement(int width, int height, std::vector<bool> measured, int first_spp, RefinementLimits limits, Pass pass,
             PassSeed seed, const char* who);

  /// Adds passes for about `seconds` (at least one pass, none once converged). Safe to call from
  /// several threads (one refines at a time). If the progress sink throws (cancellation), the
  /// pass under way is dropped and the state is what it was before it.
  RefinementState refine(double seconds, ProgressSink& progress = null_progress());

  /// Drops every pass so far (the state starts again at 0 samples); later passes take new seeds.
  /// For a pass function that switches to a better estimator: called from within a pass, the
  /// image it returns becomes the first pass. Also where a pass function may change how many
  /// samples each pixel takes (adaptive sampling: render/adaptive_sampling.h): with pixel p taking
  /// spp x share_p in every pass until the next restart, its passes still weigh their spp (the
  /// share cancels), and shares chosen from the dropped passes' noise do not bias the mean.
  void restart();

  RefinementState state() const;
  /// The mean of every pass so far (a black image before the first).
  Image image() const;
  /// Both halves' means and samples; empty images and 0 samples while either half is empty.
  RefinementHalves halves() const;
  int width() const { return width_; }
  int height() const { return height_; }

private:
  Image mean_locked() const;  ///< image(), with state_mutex_ held
  void add_pass(const Image& pass, int spp, double seconds);

  int width_, height_;
  std::vector<bool> measured_;
  int first_spp_;
  RefinementLimits limits_;
  Pass pass_;
  PassSeed seed_;
  std::mutex refining_;             ///< held by the thread that renders a pass
  mutable std::mutex state_mutex_;  ///< guards the sums and the state
  std::vector<double> sum_[2];      ///< per half: the sum of spp x pass image
  int half_spp_[2] = {0, 0};
  RefinementState state_;
  int seeds_used_ = 0;  ///< passes rendered, restarts included: pass k takes seed_(k)
};

}  // namespace matlas::render
