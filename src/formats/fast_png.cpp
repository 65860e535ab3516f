#include "formats/fast_png.h"

#include <array>
#include <cstdint>
#include <vector>

#include <zlib.h>

#include "core/error.h"
#include "formats/srgb8_encoder.h"

namespace matlas {

namespace {

void put32(std::string& out, std::uint32_t v) {
  const char b[4] = {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                     static_cast<char>(v)};
  out.append(b, 4);
}

void chunk(std::string& out, const char type[4], const unsigned char* data, std::size_t size) {
  put32(out, static_cast<std::uint32_t>(size));
  const std::size_t start = out.size();
  out.append(type, 4);
  out.append(reinterpret_cast<const char*>(data), size);
  const auto crc = crc32(0L, reinterpret_cast<const Bytef*>(out.data() + start), static_cast<uInt>(size + 4));
  put32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::string encode_png_fast_srgb8(const unsigned char* pixels, int width, int height) {
  if (width <= 0 || height <= 0) throw Error("png: empty image");
  const std::size_t stride = static_cast<std::size_t>(width) * 3;
  // Filter "Sub" on every row: each byte minus the byte of the pixel to its left.
  std::vector<unsigned char> filtered((stride + 1) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    const unsigned char* row = pixels + stride * static_cast<std::size_t>(y);
    unsigned char* f = filtered.data() + (stride + 1) * static_cast<std::size_t>(y);
    f[0] = 1;
    for (std::size_t i = 0; i < stride; ++i)
      f[1 + i] = static_cast<unsigned char>(row[i] - (i >= 3 ? row[i - 3] : 0));
  }
  uLongf packed_size = compressBound(static_cast<uLong>(filtered.size()));
  std::vector<unsigned char> packed(packed_size);
  if (compress2(packed.data(), &packed_size, filtered.data(), static_cast<uLong>(filtered.size()), 1) != Z_OK)
    throw Error("png: zlib compression failed");

  std::string out("\x89PNG\r\n\x1a\n", 8);
  std::array<unsigned char, 13> ihdr{};
  const auto w = static_cast<std::uint32_t>(width), h = static_cast<std::uint32_t>(height);
  for (int i = 0; i < 4; ++i) {
    ihdr[static_cast<std::size_t>(i)] = static_cast<unsigned char>(w >> (24 - 8 * i));
    ihdr[static_cast<std::size_t>(4 + i)] = static_cast<unsigned char>(h >> (24 - 8 * i));
  }
  ihdr[8] = 8;  // bit depth
  ihdr[9] = 2;  // colour type: RGB
  // compression, filter method and interlace: 0
  chunk(out, "IHDR", ihdr.data(), ihdr.size());
  chunk(out, "IDAT", packed.data(), packed_size);
  chunk(out, "IEND", nullptr, 0);
  return out;
}

std::string encode_png_fast(const Image& image, const ToneMap& tone) {
  std::vector<unsigned char> pixels(image.rgb.size());
  Srgb8Encoder(tone).encode(image.rgb.data(), pixels.data(), pixels.size());
  return encode_png_fast_srgb8(pixels.data(), image.width, image.height);
}

}  // namespace matlas
