// Image files: EXR (float and half) and PNG round trips, sRGB transfer, tone mapping, errors.
#include <gtest/gtest.h>

#include <cmath>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/half_float.h"
#include "formats/image_io.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

Image gradient(int w, int h) {
  Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = im.pixel(x, y);
      p[0] = 0.01f * static_cast<float>(x);
      p[1] = 3.5f * static_cast<float>(y) / static_cast<float>(h);
      p[2] = static_cast<float>(x * y) + 0.125f;
    }
  return im;
}

TEST(ImageIo, ExrRoundTripsFloatExactlyAndHalfToHalfPrecision) {
  test::TempDir dir;
  const Image im = gradient(13, 7);
  write_exr(dir / "a.exr", im);
  const Image back = read_image(dir / "a.exr");
  ASSERT_EQ(back.width, 13);
  ASSERT_EQ(back.height, 7);
  EXPECT_EQ(back.rgb, im.rgb);
  write_exr(dir / "h.exr", im, /*half=*/true);
  const Image half = read_image(dir / "h.exr");
  for (std::size_t k = 0; k < im.rgb.size(); ++k) {
    EXPECT_EQ(half.rgb[k], half_to_float(float_to_half(im.rgb[k])));
  }
  const std::string bytes = encode_exr(im);
  EXPECT_EQ(read_exr_memory(bytes.data(), bytes.size(), "memory").rgb, im.rgb);
}

TEST(ImageIo, PngRoundTripThroughSrgb) {
  test::TempDir dir;
  Image im(4, 2);
  for (std::size_t k = 0; k < im.rgb.size(); ++k) im.rgb[k] = static_cast<float>(k) / 24.0f;
  write_image(dir / "a.png", im);
  const Image back = read_image(dir / "a.png");
  ASSERT_EQ(back.width, 4);
  for (std::size_t k = 0; k < im.rgb.size(); ++k) EXPECT_NEAR(back.rgb[k], im.rgb[k], 0.01);
  const std::string png = encode_png(im);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST(ImageIo, SrgbTransferAndToneMapping) {
  EXPECT_NEAR(srgb_encode(0.5f), 0.7354f, 1e-4);
  EXPECT_NEAR(srgb_decode(srgb_encode(0.2f)), 0.2f, 1e-6);
  EXPECT_NEAR(srgb_encode(0.001f), 0.01292f, 1e-6);
  EXPECT_EQ(tone_map_to_srgb8(0.0f, {}), 0);
  EXPECT_EQ(tone_map_to_srgb8(1.0f, {}), 255);
  EXPECT_EQ(tone_map_to_srgb8(7.0f, {}), 255);
  EXPECT_EQ(tone_map_to_srgb8(-1.0f, {}), 0);
  EXPECT_EQ(tone_map_to_srgb8(NAN, {}), 0);
  ToneMap up;
  up.exposure = 1.0;
  EXPECT_EQ(tone_map_to_srgb8(0.25f, up), tone_map_to_srgb8(0.5f, {}));
  ToneMap reinhard{ToneMap::Curve::reinhard, 0.0};
  EXPECT_EQ(tone_map_to_srgb8(1.0f, reinhard), tone_map_to_srgb8(0.5f, {}));
  EXPECT_LT(tone_map_to_srgb8(100.0f, reinhard), 255);
}

TEST(ImageIo, ErrorsNameTheFile) {
  test::TempDir dir;
  write_file_atomic(dir / "bad.exr", std::string("definitely not an exr"));
  for (const std::string name : {"bad.exr", "missing.exr", "x.tiff"}) {
    try {
      read_image(dir / name);
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(write_image(dir / "a.bmp", gradient(2, 2)), Error);
  EXPECT_THROW(encode_png(Image()), Error);
}

}  // namespace
}  // namespace matlas
