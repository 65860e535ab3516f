#pragma once
// Automatic exposure of a linear image: the exposure (in stops, as ToneMap::exposure) that maps
// its log-average luminance to middle grey (0.18), Reinhard et al. 2002's "key" of a scene:
//
//   L_avg = exp(mean over pixels of log(1e-4 + L)),   exposure = log2(0.18 / L_avg)
//
// with L the Rec. 709 luminance. Bright walls and floors of a GI scene then sit near middle grey
// instead of white, and a dark scene is brightened. Pixels outside `mask` (when given, one per
// pixel) are ignored; the result is clamped to [-16, 16] stops, 0 for an empty or black image.
#include <vector>

#include "formats/image_io.h"

namespace matlas::render {

double auto_exposure(const Image& image, const std::vector<bool>& mask = {});

}  // namespace matlas::render
