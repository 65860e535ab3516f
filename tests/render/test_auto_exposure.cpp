// Automatic exposure: middle grey for the log-average luminance (Reinhard's key).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render/auto_exposure.h"

namespace matlas::render {
namespace {

Image exposure_filled(int w, int h, float r, float g, float b) {
  Image im(w, h);
  for (std::size_t p = 0; p < im.pixel_count(); ++p) {
    im.rgb[3 * p] = r;
    im.rgb[3 * p + 1] = g;
    im.rgb[3 * p + 2] = b;
  }
  return im;
}

TEST(AutoExposure, MapsTheLogAverageLuminanceToMiddleGrey) {
  // Grey 0.72: two stops down. Luminance weights: pure green 1.0 has luminance 0.7152.
  EXPECT_NEAR(auto_exposure(exposure_filled(4, 4, 0.72f, 0.72f, 0.72f)), std::log2(0.18 / (0.72 + 1e-4)), 1e-6);
  EXPECT_NEAR(auto_exposure(exposure_filled(4, 4, 0.0f, 1.0f, 0.0f)), std::log2(0.18 / (0.7152 + 1e-4)), 1e-6);
  // Half the pixels 4x brighter: the log-average (geometric mean) is 2x, one stop less.
  Image half = exposure_filled(4, 4, 0.1f, 0.1f, 0.1f);
  for (std::size_t p = 0; p < 8; ++p) half.rgb[3 * p] = half.rgb[3 * p + 1] = half.rgb[3 * p + 2] = 0.4f;
  EXPECT_NEAR(auto_exposure(half), std::log2(0.18 / std::sqrt((0.1 + 1e-4) * (0.4 + 1e-4))), 1e-6);
}

TEST(AutoExposure, AMaskSelectsThePixelsAndBlackGivesZero) {
  Image im = exposure_filled(2, 1, 0.18f, 0.18f, 0.18f);
  im.rgb[3] = im.rgb[4] = im.rgb[5] = 1000.0f;  // a blown-out second pixel, masked out
  EXPECT_NEAR(auto_exposure(im, {true, false}), std::log2(0.18 / (0.18 + 1e-4)), 1e-6);
  EXPECT_EQ(auto_exposure(exposure_filled(3, 3, 0, 0, 0)), 0.0);
  EXPECT_EQ(auto_exposure(Image()), 0.0);
  EXPECT_NEAR(auto_exposure(exposure_filled(1, 1, 1e-30f, 1e-30f, 1e-30f)), std::log2(0.18 / 1e-4), 1e-9);  // the 1e-4 floor
}

}  // namespace
}  // namespace matlas::render
