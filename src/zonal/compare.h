#pragma once
// Error of an image against a Monte Carlo reference rendered twice (two seeds), over the pixels
// fully covered by the object (render::object_coverage == 1), all channels. With R = (R1 + R2)/2:
//
//   l1    = sum |Z - R| / sum |R|                        (includes R's noise)
//   rms   = sqrt(max(0, sum (Z - R)^2 - sum (R1 - R2)^2 / 4) / sum R^2)
//   noise = sum |R1 - R2| / 2 / sum |R|                  (about R's own noise in l1 units)
//
// rms is the noise-free relative RMS error: E (Z - R)^2 = bias^2 + var/2 and E (R1 - R2)^2 = 2 var
// per value, so subtracting a quarter of the seeds' squared difference removes the reference's
// noise (0 when the difference is below the noise).
#include <vector>

#include "formats/image_io.h"

namespace matlas::zonal {

struct ImageErrors {
  double l1 = 0, rms = 0, noise = 0;
};

/// Throws matlas::Error when the images and coverage differ in size or nothing is covered.
ImageErrors compare_to_reference(const Image& z, const Image& r1, const Image& r2, const std::vector<float>& coverage);

}  // namespace matlas::zonal
