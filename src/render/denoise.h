#pragma once
// Dual-buffer non-local means for the refined previews: a biased, consistent denoiser that takes
// two independent unbiased estimates of one image (the halves A and B that
// render/progressive_render.h keeps) and uses their difference as the per-pixel noise level
// (Rousselle, Knaus & Zwicker 2012, "Adaptive Rendering with Non-Local Means Filtering").
//
// Each half is filtered with weights computed on the OTHER half (cross filtering: the weights do
// not depend on the noise of the values they average), and the two filtered halves are combined
// by their samples. The weight of a neighbour q of p (within `search_radius`) compares the patches
// around p and q (`patch_radius`) in the guide half G with variance V:
//
//     d^2(p, q) = mean over the patch and the channels of
//                 [(G(p') - G(q'))^2 - (V(p') + min(V(p'), V(q')))] / (eps + k^2 (V(p') + V(q'))),
//     w(p, q)   = exp(-max(0, d^2)),
//
// so neighbours are averaged only while their difference is within about k noise standard
// deviations of what noise alone explains. V comes from the halves: Var(A - B) = (A - B)^2 per
// pixel, averaged over the channels and its 3 x 3 neighbourhood, split as Var(A) = Var(A - B)
// b / (a + b) and Var(B) = Var(A - B) a / (a + b). The filter is consistent: as the samples grow,
// V falls, the weights of differing neighbours vanish and the result tends to the plain mean (a
// noise-free input comes back unchanged). Its bias is not estimated here: the figures against a
// long reference are in docs/RENDERING.md, and the browser labels a denoised image as such.
//
// `region` keeps what must not mix apart: pixels are averaged only with pixels of the same label,
// and label 0 marks pixels left as they are (a preview's partially covered silhouette).
#include <cstdint>
#include <vector>

#include "formats/image_io.h"

namespace matlas::render {

struct DenoiseSettings {
  // The defaults, from a sweep against 1024-spp references of previews (128 x 128 sphere, studio,
  // 32-128 spp; search radii 4-12, patch radii 1-3, strengths 0.3-2.5; docs/RENDERING.md,
  // "Denoising"): larger windows average across the shading's gradients; k = 1.5 halves a
  // metallic paint's error but doubles a chrome's or a phenolic's at 32-64 spp (their highlights
  // are blurred), k = 0.45 leaves those as they are and still takes 40 % off the paint's.
  int search_radius = 4;   ///< neighbours within a (2r + 1)^2 window
  int patch_radius = 2;    ///< patches of (2f + 1)^2 pixels compared
  double strength = 0.45;  ///< k above
  /// Throws matlas::Error for a negative radius, a search radius above 32 or a strength that is
  /// not positive and finite.
  void validate() const;
};

struct DenoiseResult {
  Image image;
  /// The estimated RMS noise left, relative to the image's RMS over the pixels of `measured`
  /// (all pixels if empty): from the two filtered halves as ProgressiveRender estimates the mean's
  /// error. Variance only: the filter's bias is not in it.
  double relative_error = 0;
};

/// a, b: the two halves (means of `samples_a` and `samples_b` samples per pixel, same size);
/// region: one label per pixel or empty (one region). Throws matlas::Error for halves of different
/// sizes, a region of the wrong size, non-positive sample counts or invalid settings.
DenoiseResult denoise_halves(const Image& a, const Image& b, double samples_a, double samples_b,
                             const std::vector<std::uint8_t>& region, const std::vector<bool>& measured = {},
                             const DenoiseSettings& settings = {});

}  // namespace matlas::render
