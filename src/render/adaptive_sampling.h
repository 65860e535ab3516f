#pragma once
// Adaptive sampling: each pixel's share of a refinement's samples, from the noise of two
// independent estimates of the image.
//
// The error of a preview is not spread evenly: under the studio environment 0.1 % of chrome's
// pixels (the bright light reflected along the sphere's top rim, a strip a few pixels tall whose
// every pixel straddles an edge of the light) hold 99 % of its variance; the paint's variance sits
// in its highlights. For a fixed number of samples the total variance sum_p sigma_p^2 / n_p is least
// with n_p proportional to sigma_p, the standard deviation of ONE sample of pixel p
// (docs/RENDERING.md "Adaptive sampling" measures the gain).
//
// Estimate. Two independent estimates a and b of pixel p, made of n_p samples together (half
// each), differ by a - b of variance 4 sigma_p^2 / n_p, so sigma_p^2 is estimated by
// n_p (a - b)^2 / 4 summed over the channels. One difference is a poor estimate of one pixel; the
// estimates are averaged over the (2 radius + 1)^2 pixels around it (noise clusters along edges
// and highlights), and the shares are sigma_p / lambda clamped to [floor, cap], lambda chosen so
// that they average 1 (the passes' cost stays). The floor keeps every pixel converging.
//
// Bias. The shares depend on the noise of the estimates they came from: those estimates must not
// enter the image weighted by them (render/refinement.h: Refinement::restart drops them).
#include <vector>

#include "formats/image_io.h"

namespace matlas::render {

struct AdaptiveSampling {
  bool enabled = true;
  double floor = 0.125;  ///< the least share of a pixel (of the image's mean)
  double cap = 64;       ///< the largest share of a pixel
  int radius = 1;        ///< the noise estimates are averaged over (2 radius + 1)^2 pixels
  /// A refinement's trial (its two halves) is the first pass after the first with at least this
  /// many samples per pixel: fewer make a poor estimate of each pixel's noise.
  int min_trial_spp = 8;
  /// Throws matlas::Error for a floor outside (0, 1], a cap below 1 or above 4096, a radius
  /// outside [0, 8] or a min_trial_spp below 2.
  void validate() const;
};

/// A pixel's camera samples in a pass of `spp` when it takes `share` of them: max(1, round(spp x
/// share)) (RenderSettings::pixel_samples, pathtrace::TraceSettings::pixel_samples).
int pixel_sample_count(int spp, double share);

/// Throws matlas::Error unless `shares` (when not null) has one positive, finite share per pixel
/// of a width x height image.
void check_pixel_samples(const std::vector<double>* shares, int width, int height);

/// The shares (row-major, mean 1) from two independent estimates `a`, `b` of one image made
/// with `samples[p]` camera samples in pixel p together. `weights` (3 per pixel, empty: 1) weigh
/// each channel's squared error: the shares then minimise the weighted sum of the variances
/// (n_p proportional to the root of sum_c w_pc sigma_pc^2). Without any difference between the
/// estimates (a noise-free image): 1 everywhere.
std::vector<double> adaptive_pixel_samples(const Image& a, const Image& b, const std::vector<int>& samples,
                                           const AdaptiveSampling& settings = {},
                                           const std::vector<double>& weights = {});

/// Weights for adaptive_pixel_samples that count an image's error twice, as a linear figure and
/// as shown, each relative to the image's size in that form over the `measured` pixels: per
/// pixel and channel 1 / sum v^2 + D'(v)^2 / sum D(v)^2, where v is `image`'s value and D the
/// displayed value (`tone`, then sRGB). The linear term alone sends the samples to bright
/// highlights that the tone curve saturates (under the studio lights 99 % of chrome's linear
/// variance sits in 0.1 % of its pixels); the shown term alone would starve them, though their
/// linear error is what a renderer or an exported image sees.
std::vector<double> linear_and_shown_weights(const Image& image, const std::vector<bool>& measured, const ToneMap& tone);

}  // namespace matlas::render
