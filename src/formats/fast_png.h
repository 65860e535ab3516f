#pragma once
// A fast PNG encoder for live previews: tone mapping through formats/image_io.h, then the "Sub"
// row filter and zlib at level 1 (about 5-10x faster than the general-purpose writer at its
// default level, for files about 1.5x larger, which on loopback costs nothing). The output is a
// standard 8-bit RGB PNG that every decoder reads.
#include <string>

#include "formats/image_io.h"

namespace matlas {

/// PNG bytes of a linear image tone-mapped by `tone`.
std::string encode_png_fast(const Image& image, const ToneMap& tone);

/// PNG bytes of 8-bit sRGB pixels (width * height * 3, rows top first).
std::string encode_png_fast_srgb8(const unsigned char* pixels, int width, int height);

}  // namespace matlas
