#include "render/text.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <vector>

#include <stb/stb_truetype.h>

namespace matlas::render {

namespace {

struct Font {
  std::vector<unsigned char> data;
  stbtt_fontinfo info{};
  bool ok = false;
};

const Font& font() {
  static const Font f = [] {
    Font font;
    const char* env = std::getenv("MATLAS_FONT");
    const std::string path = env && *env ? env : "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    std::ifstream in(path, std::ios::binary);
    if (!in) return font;
    font.data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    font.ok = !font.data.empty() &&
              stbtt_InitFont(&font.info, font.data.data(), stbtt_GetFontOffsetForIndex(font.data.data(), 0)) != 0;
    return font;
  }();
  return f;
}

/// Coverage bitmap of the text line (w x h), baseline placed at `ascent`.
std::vector<float> rasterize(const std::string& text, float size, int* w, int* h) {
  const Font& f = font();
  const float scale = stbtt_ScaleForPixelHeight(&f.info, size);
  int ascent, descent, gap;
  stbtt_GetFontVMetrics(&f.info, &ascent, &descent, &gap);
  *w = text_width(text, size) + 2;
  *h = static_cast<int>(std::ceil((ascent - descent) * scale)) + 2;
  std::vector<float> cover(static_cast<std::size_t>(*w) * static_cast<std::size_t>(*h), 0.0f);
  const int baseline = static_cast<int>(std::round(ascent * scale)) + 1;
  float pen = 1.0f;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const int c = static_cast<unsigned char>(text[i]);
    int advance, bearing;
    stbtt_GetCodepointHMetrics(&f.info, c, &advance, &bearing);
    int x0, y0, x1, y1;
    stbtt_GetCodepointBitmapBox(&f.info, c, scale, scale, &x0, &y0, &x1, &y1);
    const int gw = x1 - x0, gh = y1 - y0;
    if (gw > 0 && gh > 0) {
      std::vector<unsigned char> glyph(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
      stbtt_MakeCodepointBitmap(&f.info, glyph.data(), gw, gh, gw, scale, scale, c);
      const int ox = static_cast<int>(std::round(pen)) + x0, oy = baseline + y0;
      for (int y = 0; y < gh; ++y)
        for (int x = 0; x < gw; ++x) {
          const int tx = ox + x, ty = oy + y;
          if (tx < 0 || ty < 0 || tx >= *w || ty >= *h) continue;
          float& d = cover[static_cast<std::size_t>(ty) * static_cast<std::size_t>(*w) + static_cast<std::size_t>(tx)];
          d = std::max(d, glyph[static_cast<std::size_t>(y) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(x)] / 255.0f);
        }
    }
    pen += advance * scale;
    if (i + 1 < text.size())
      pen += scale * stbtt_GetCodepointKernAdvance(&f.info, c, static_cast<unsigned char>(text[i + 1]));
  }
  return cover;
}

}  // namespace

bool text_available() { return font().ok; }

int text_width(const std::string& text, float size) {
  const Font& f = font();
  if (!f.ok) return 0;
  const float scale = stbtt_ScaleForPixelHeight(&f.info, size);
  float pen = 0;
  for (unsigned char c : text) {
    int advance, bearing;
    stbtt_GetCodepointHMetrics(&f.info, c, &advance, &bearing);
    pen += advance * scale;
  }
  return static_cast<int>(std::ceil(pen));
}

bool draw_text(Image& image, int x, int y, const std::string& text, float size, const Rgb& colour) {
  if (!font().ok || text.empty()) return false;
  int w, h;
  const std::vector<float> cover = rasterize(text, size, &w, &h);
  auto at = [&](int cx, int cy) {
    return (cx < 0 || cy < 0 || cx >= w || cy >= h) ? 0.0f
                                                    : cover[static_cast<std::size_t>(cy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(cx)];
  };
  for (int ty = -1; ty <= h; ++ty)
    for (int tx = -1; tx <= w; ++tx) {
      const int px = x + tx, py = y + ty;
      if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
      float outline = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) outline = std::max(outline, at(tx + dx, ty + dy));
      const float a = at(tx, ty);
      float* p = image.pixel(px, py);
      for (int c = 0; c < 3; ++c) {
        p[c] *= 1.0f - 0.6f * outline;  // darken behind the glyphs
        p[c] = p[c] * (1.0f - a) + static_cast<float>(colour[c]) * a;
      }
    }
  return true;
}

}  // namespace matlas::render
