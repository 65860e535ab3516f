// Image files. EXR reading uses OpenEXR (every compression, DWA included, which tinyexr lacks),
// EXR writing uses tinyexr; PNG/HDR use stb (libstb's compiled implementation).
#include "formats/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace matlas {

namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// An OpenEXR input stream over a memory buffer.
class MemoryStream final : public Imf::IStream {
public:
  MemoryStream(const char* data, std::size_t size, const std::string& name)
      : Imf::IStream(name.c_str()), data_(data), size_(size) {}
  bool read(char c[], int n) override {
    if (n < 0 || pos_ + static_cast<std::size_t>(n) > size_)
      throw Error(fileName() + std::string(": unexpected end of EXR data"));
    std::memcpy(c, data_ + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return pos_ < size_;
  }
  std::uint64_t tellg() override { return pos_; }
  void seekg(std::uint64_t pos) override { pos_ = static_cast<std::size_t>(pos); }
  void clear() override {}

private:
  const char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

float aces(float x) {
  const float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
  return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
}

void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}

Image from_stb_8bit(const unsigned char* pixels, int w, int h) {
  Image image(w, h);
  float table[256];
  for (int i = 0; i < 256; ++i) table[i] = srgb_decode(static_cast<float>(i) / 255.0f);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = table[pixels[i]];
  return image;
}

}  // namespace

float srgb_encode(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) {
  const float x = std::clamp(encoded, 0.0f, 1.0f);
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

float tone_curve(float linear, float scale, ToneMap::Curve curve) {
  float x = std::isfinite(linear) ? std::max(linear, 0.0f) : 0.0f;
  x *= scale;
  switch (curve) {
    case ToneMap::Curve::clamp: break;
    case ToneMap::Curve::reinhard: x = x / (1.0f + x); break;
    case ToneMap::Curve::aces: x = aces(x); break;
  }
  return x;
}

unsigned char srgb8_code(float x) { return static_cast<unsigned char>(std::lround(srgb_encode(x) * 255.0f)); }

unsigned char tone_map_to_srgb8(float linear, const ToneMap& tone) {
  return srgb8_code(tone_curve(linear, static_cast<float>(std::exp2(tone.exposure)), tone.curve));
}

Image read_exr_memory(const void* data, std::size_t bytes, const std::string& name) {
  try {
    MemoryStream stream(static_cast<const char*>(data), bytes, name);
    Imf::InputFile file(stream);
    const Imath::Box2i window = file.header().dataWindow();
    const int w = window.max.x - window.min.x + 1;
    const int h = window.max.y - window.min.y + 1;
    if (w <= 0 || h <= 0) throw file_error(name, "EXR image has an empty data window");
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb = channels.findChannel("R") && channels.findChannel("G") &&
                     channels.findChannel("B");
    const bool luminance = channels.findChannel("Y") != nullptr;
    if (!rgb && !luminance) throw file_error(name, "EXR image has neither R, G, B nor Y channels");
    Image image(w, h);
    Imf::FrameBuffer frame;
    const std::size_t xs = 3 * sizeof(float), ys = xs * static_cast<std::size_t>(w);
    // Slices are addressed by absolute data-window coordinates.
    char* base = reinterpret_cast<char*>(image.rgb.data()) -
                 static_cast<std::ptrdiff_t>(window.min.x) * static_cast<std::ptrdiff_t>(xs) -
                 static_cast<std::ptrdiff_t>(window.min.y) * static_cast<std::ptrdiff_t>(ys);
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < (rgb ? 3 : 1); ++c)
      frame.insert(rgb ? names[c] : "Y",
                   Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys, 1, 1, 0.0));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (!rgb)
      for (std::size_t p = 0; p < image.pixel_count(); ++p)
        image.rgb[3 * p + 1] = image.rgb[3 * p + 2] = image.rgb[3 * p];
    for (float v : image.rgb)
      if (!std::isfinite(v)) throw file_error(name, "EXR image has NaN or infinite pixels");
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw file_error(name, std::string("cannot read EXR image: ") + e.what());
  }
}

Image read_image(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  const std::string bytes = read_file(path);
  if (ext == ".exr") return read_exr_memory(bytes.data(), bytes.size(), path.string());
  if (ext != ".hdr" && ext != ".png" && ext != ".jpg" && ext != ".jpeg")
    throw file_error(path, "unknown image extension (expected .exr, .hdr, .png or .jpg)");
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw file_error(path, "image file too large");
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());
  int w = 0, h = 0, n = 0;
  if (ext == ".hdr") {
    std::unique_ptr<float, void (*)(void*)> pixels(stbi_loadf_from_memory(data, size, &w, &h, &n, 3),
                                                   stbi_image_free);
    if (!pixels) throw file_error(path, std::string("cannot read image: ") + stbi_failure_reason());
    Image image(w, h);
    std::copy_n(pixels.get(), image.rgb.size(), image.rgb.data());
    return image;
  }
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_memory(data, size, &w, &h, &n, 3),
                                                   stbi_image_free);
  if (!pixels) throw file_error(path, std::string("cannot read image: ") + stbi_failure_reason());
  return from_stb_8bit(pixels.get(), w, h);
}

std::string encode_exr(const Image& image, bool half) {
  if (image.empty()) throw Error("cannot encode an empty image as EXR");
  // tinyexr wants planar channels, in B, G, R order (what most viewers expect).
  const std::size_t n = image.pixel_count();
  std::vector<float> planes[3];
  for (auto& p : planes) p.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) planes[c][i] = image.rgb[3 * i + static_cast<std::size_t>(c)];
  float* pointers[3] = {planes[2].data(), planes[1].data(), planes[0].data()};

  EXRHeader header;
  InitEXRHeader(&header);
  EXRImage exr;
  InitEXRImage(&exr);
  exr.num_channels = 3;
  exr.images = reinterpret_cast<unsigned char**>(pointers);
  exr.width = image.width;
  exr.height = image.height;
  EXRChannelInfo channels[3];
  const char* names[3] = {"B", "G", "R"};
  int pixel_types[3], requested[3];
  for (int c = 0; c < 3; ++c) {
    std::memset(&channels[c], 0, sizeof(EXRChannelInfo));
    channels[c].name[0] = names[c][0];
    pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
    requested[c] = half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT;
  }
  header.num_channels = 3;
  header.channels = channels;
  header.pixel_types = pixel_types;
  header.requested_pixel_types = requested;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

  unsigned char* memory = nullptr;
  const char* err = nullptr;
  const std::size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
  if (size == 0 || memory == nullptr) {
    std::string what = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    throw Error("cannot encode EXR image: " + what);
  }
  std::string out(reinterpret_cast<const char*>(memory), size);
  std::free(memory);
  return out;
}

void write_exr(const std::filesystem::path& path, const Image& image, bool half) {
  write_file_atomic(path, encode_exr(image, half));
}

std::string encode_png_srgb8(const unsigned char* pixels, int width, int height) {
  std::string out;
  if (!stbi_write_png_to_func(append_bytes, &out, width, height, 3, pixels, width * 3))
    throw Error("cannot encode PNG image");
  return out;
}

std::string encode_png_srgba8(const unsigned char* pixels, int width, int height) {
  std::string out;
  if (!stbi_write_png_to_func(append_bytes, &out, width, height, 4, pixels, width * 4))
    throw Error("cannot encode PNG image");
  return out;
}

std::string encode_png(const Image& image, const ToneMap& tone) {
  if (image.empty()) throw Error("cannot encode an empty image as PNG");
  std::vector<unsigned char> pixels(image.rgb.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = tone_map_to_srgb8(image.rgb[i], tone);
  return encode_png_srgb8(pixels.data(), image.width, image.height);
}

void write_png(const std::filesystem::path& path, const Image& image, const ToneMap& tone) {
  write_file_atomic(path, encode_png(image, tone));
}

void write_image(const std::filesystem::path& path, const Image& image, const ToneMap& tone) {
  const std::string ext = lower_extension(path);
  if (ext == ".exr") return write_exr(path, image);
  if (ext == ".png") return write_png(path, image, tone);
  throw file_error(path, "unknown output image extension (expected .exr or .png)");
}

}  // namespace matlas
