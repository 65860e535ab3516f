// The fast preview PNG encoder, checked by decoding its files with the general image reader.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/atomic_file.h"
#include "formats/image_io.h"
#include "formats/fast_png.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

TEST(FastPng, DecodesToTheSamePixels) {
  test::TempDir dir("matlas-png");
  const int w = 37, h = 23;
  std::mt19937 rng(7);
  std::vector<unsigned char> pixels(static_cast<std::size_t>(w) * h * 3);
  for (auto& p : pixels) p = static_cast<unsigned char>(rng() & 0xff);
  const std::string png = encode_png_fast_srgb8(pixels.data(), w, h);
  write_file_atomic(dir / "a.png", png);
  const Image back = read_image(dir / "a.png");  // decoded to linear
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  for (std::size_t i = 0; i < pixels.size(); ++i)
    ASSERT_EQ(std::lround(255.0f * srgb_encode(back.rgb[i])), pixels[i]) << "value " << i;
}

TEST(FastPng, ToneMapsLikeTheGeneralEncoder) {
  test::TempDir dir("matlas-png");
  Image im(16, 8);
  for (std::size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = 0.02f * static_cast<float>(i % 97);
  const ToneMap tone{ToneMap::Curve::aces, 0.5};
  write_file_atomic(dir / "fast.png", encode_png_fast(im, tone));
  write_file_atomic(dir / "ref.png", encode_png(im, tone));
  const Image a = read_image(dir / "fast.png"), b = read_image(dir / "ref.png");
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (std::size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "value " << i;
}

}  // namespace
}  // namespace matlas
