#pragma once
// Text labels on images with stb_truetype and the DejaVu Sans font (Debian fonts-dejavu-core).
// Without the font file labels are silently skipped (draw_text returns false).
#include <string>

#include "brdf/types.h"
#include "formats/image_io.h"

namespace matlas::render {

/// Whether a font is available (MATLAS_FONT, else /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf).
bool text_available();
/// Draws `text` with its top-left corner at (x, y), `size` pixels tall, blended over the linear
/// image in `colour` with a dark outline for legibility. Returns false without a font.
bool draw_text(Image& image, int x, int y, const std::string& text, float size, const Rgb& colour);
/// Width in pixels of `text` at `size` (0 without a font).
int text_width(const std::string& text, float size);

}  // namespace matlas::render
