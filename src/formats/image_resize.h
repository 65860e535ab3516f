#pragma once
// Area-averaging resampling of linear images (for smaller previews: thumbnails, drag previews,
// path strips), so that downsized previews keep the energy of the full-size ones.
#include "formats/image_io.h"

namespace matlas {

/// Each output pixel is the area-weighted mean of the input pixels it covers.
Image resize_area(const Image& image, int width, int height);

}  // namespace matlas
