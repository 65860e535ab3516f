// The firefly filter (render/firefly_filter.h): a lone bright pixel becomes the median of its
// neighbours; a highlight that falls off over its neighbours, an edge and a smooth image are kept.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "render/firefly_filter.h"

namespace matlas::render {
namespace {

Image grey(int w, int h, float v) {
  Image im(w, h);
  std::fill(im.rgb.begin(), im.rgb.end(), v);
  return im;
}

TEST(FireflyFilter, ALoneBrightPixelTakesItsNeighboursMedian) {
  Image im = grey(8, 8, 0.5f);
  im.pixel(3, 4)[0] = 40.0f, im.pixel(3, 4)[1] = 30.0f, im.pixel(3, 4)[2] = 20.0f;
  im.pixel(2, 4)[1] = 0.7f;  // neighbours that differ: the median, not one of them
  im.pixel(4, 4)[1] = 0.6f;
  EXPECT_EQ(remove_fireflies(im), 1);
  EXPECT_FLOAT_EQ(im.pixel(3, 4)[0], 0.5f);
  EXPECT_FLOAT_EQ(im.pixel(3, 4)[1], 0.5f);
  EXPECT_FLOAT_EQ(im.pixel(3, 4)[2], 0.5f);
  // In a corner too (three neighbours).
  im.pixel(0, 0)[0] = im.pixel(0, 0)[1] = im.pixel(0, 0)[2] = 50.0f;
  EXPECT_EQ(remove_fireflies(im), 1);
  EXPECT_FLOAT_EQ(im.pixel(0, 0)[1], 0.5f);
}

TEST(FireflyFilter, HighlightsEdgesAndSmoothImagesAreKept) {
  Image im = grey(9, 9, 0.2f);
  // A highlight: 10 at the centre, 4 around it (ratio 2.5 < 4), 1 further out.
  for (int y = 2; y <= 6; ++y)
    for (int x = 2; x <= 6; ++x) std::fill(im.pixel(x, y), im.pixel(x, y) + 3, 1.0f);
  for (int y = 3; y <= 5; ++y)
    for (int x = 3; x <= 5; ++x) std::fill(im.pixel(x, y), im.pixel(x, y) + 3, 4.0f);
  std::fill(im.pixel(4, 4), im.pixel(4, 4) + 3, 10.0f);
  // An edge: a bright half-plane at the right.
  for (int y = 0; y < 9; ++y) std::fill(im.pixel(8, y), im.pixel(8, y) + 3, 50.0f);
  const Image before = im;
  EXPECT_EQ(remove_fireflies(im), 0);
  EXPECT_EQ(im.rgb, before.rgb);
  // A stricter ratio takes the highlight's peak (2.5x its brightest neighbour).
  EXPECT_EQ(remove_fireflies(im, 2.0), 1);
  EXPECT_FLOAT_EQ(im.pixel(4, 4)[0], 4.0f);
  EXPECT_THROW(remove_fireflies(im, 0.5), Error);
}

}  // namespace
}  // namespace matlas::render
