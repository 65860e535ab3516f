#pragma once
// Images: linear RGB float pixels, and their files.
//
//   read:  OpenEXR (.exr, tinyexr; half or float, RGB or RGBA, alpha dropped), Radiance (.hdr),
//          PNG/JPEG (8-bit sRGB, decoded to linear).
//   write: OpenEXR (linear float32 or float16), PNG (tone mapped to 8-bit sRGB, in memory or file).
//
// Every writer goes through AtomicFile; every error is a matlas::Error naming the file.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace matlas {

/// A linear RGB image: `width` x `height` pixels, row-major with the top row first, 3 floats per
/// pixel (r, g, b).
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;

  Image() = default;
  /// A black image.
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}

  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * height; }
  float* pixel(int x, int y) { return rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  const float* pixel(int x, int y) const {
    return rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
  }
  bool empty() const { return rgb.empty(); }
};

/// Display transform from linear radiance to 8-bit sRGB.
struct ToneMap {
  enum class Curve {
    clamp,     ///< scale by 2^exposure, clamp to [0, 1]
    reinhard,  ///< x / (1 + x) after exposure (keeps highlights)
    aces,      ///< Narkowicz's ACES filmic fit after exposure
  };
  Curve curve = Curve::clamp;
  double exposure = 0.0;  ///< in stops
};

/// The sRGB transfer function (linear [0, 1] -> encoded [0, 1]) and its inverse.
float srgb_encode(float linear);
float srgb_decode(float encoded);

/// Applies the tone map to one linear value and returns the 8-bit sRGB code.
unsigned char tone_map_to_srgb8(float linear, const ToneMap& tone);
/// Its two parts: the tone curve after the exposure factor `scale` = 2^exposure (negative and
/// non-finite values count as 0; the clamp curve may return values above 1), and the 8-bit code
/// of the sRGB curve of a value (clamped to [0, 1]). Srgb8Encoder does both for many values.
float tone_curve(float linear, float scale, ToneMap::Curve curve);
unsigned char srgb8_code(float x);

/// Reads an image by extension (.exr, .hdr, .png, .jpg). Throws matlas::Error naming the file.
Image read_image(const std::filesystem::path& path);
/// Reads an EXR image from memory; `name` is used in error messages.
Image read_exr_memory(const void* data, std::size_t bytes, const std::string& name);

/// Linear EXR (float32 channels, or float16 with `half`), written atomically.
void write_exr(const std::filesystem::path& path, const Image& image, bool half = false);
/// The same EXR file in memory.
std::string encode_exr(const Image& image, bool half = false);

/// Tone-mapped 8-bit sRGB PNG (3 channels) in memory: the bytes of a .png file.
std::string encode_png(const Image& image, const ToneMap& tone = {});
/// An 8-bit RGB PNG of already encoded pixels (width * height * 3 bytes, row-major, top first).
std::string encode_png_srgb8(const unsigned char* pixels, int width, int height);
/// The same with an alpha channel (width * height * 4 bytes, RGBA, straight alpha).
std::string encode_png_srgba8(const unsigned char* pixels, int width, int height);
/// Tone-mapped PNG written atomically.
void write_png(const std::filesystem::path& path, const Image& image, const ToneMap& tone = {});

/// Writes `.exr` (linear) or `.png` (tone mapped) by the extension of `path`; throws
/// matlas::Error for other extensions.
void write_image(const std::filesystem::path& path, const Image& image, const ToneMap& tone = {});

}  // namespace matlas
