// The firefly filter (render/firefly_filter.h): a lone bright pixel becomes the median of its
// neighbours; a highlight that falls off over its neighbours, an edge and a smooth image are kept;
// with rank 2 a bright pair or triple goes too, and lines and a blob stay.
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
  // A highlight: 8 at the centre, 4 around it (ratio 2), 1 further out.
  for (int y = 2; y <= 6; ++y)
    for (int x = 2; x <= 6; ++x) std::fill(im.pixel(x, y), im.pixel(x, y) + 3, 1.0f);
  for (int y = 3; y <= 5; ++y)
    for (int x = 3; x <= 5; ++x) std::fill(im.pixel(x, y), im.pixel(x, y) + 3, 4.0f);
  std::fill(im.pixel(4, 4), im.pixel(4, 4) + 3, 8.0f);
  // An edge: a bright half-plane at the right.
  for (int y = 0; y < 9; ++y) std::fill(im.pixel(8, y), im.pixel(8, y) + 3, 50.0f);
  const Image before = im;
  EXPECT_EQ(remove_fireflies(im), 0);
  EXPECT_EQ(im.rgb, before.rgb);
  EXPECT_EQ(remove_fireflies(im, 3.0, 1), 0);
  // A stricter ratio takes the highlight's peak (2x its brightest neighbour).
  EXPECT_EQ(remove_fireflies(im, 1.5), 1);
  EXPECT_FLOAT_EQ(im.pixel(4, 4)[0], 4.0f);
  EXPECT_THROW(remove_fireflies(im, 0.5), Error);
}

TEST(FireflyFilter, RankTwoTakesPairsAndTriplesAndKeepsLinesAndBlobs) {
  Image im = grey(10, 10, 0.5f);
  // Two adjacent bright pixels: each is the other's brightest neighbour.
  std::fill(im.pixel(2, 2), im.pixel(2, 2) + 3, 40.0f);
  std::fill(im.pixel(3, 2), im.pixel(3, 2) + 3, 30.0f);
  Image pair = im;
  EXPECT_EQ(remove_fireflies(pair, 3.0, 1), 0);
  EXPECT_EQ(remove_fireflies(pair, 3.0, 2), 2);
  EXPECT_FLOAT_EQ(pair.pixel(2, 2)[0], 0.5f);
  EXPECT_FLOAT_EQ(pair.pixel(3, 2)[0], 0.5f);
  // Three bright pixels in an L (the firefly left in the floor scene's drag image by rank 1): the
  // brightest goes (over 2.5x its second brightest neighbour).
  Image triple = grey(8, 8, 0.05f);
  std::fill(triple.pixel(4, 4), triple.pixel(4, 4) + 3, 3.2f);
  std::fill(triple.pixel(3, 4), triple.pixel(3, 4) + 3, 1.1f);
  std::fill(triple.pixel(4, 5), triple.pixel(4, 5) + 3, 1.8f);
  EXPECT_EQ(remove_fireflies(triple, 2.5, 1), 0);
  EXPECT_GE(remove_fireflies(triple, 2.5, 2), 1);
  EXPECT_LT(triple.pixel(4, 4)[0], 1.0f);
  // A line of bright pixels that falls off at its ends, a line that ends on the border, and a
  // 2 x 2 blob: kept, at the drag image's ratio and rank.
  Image shapes = grey(12, 12, 0.5f);
  for (int x = 2; x <= 5; ++x) std::fill(shapes.pixel(x, 8), shapes.pixel(x, 8) + 3, 20.0f);
  for (const int x : {1, 6})
    for (int y = 7; y <= 9; ++y) std::fill(shapes.pixel(x, y), shapes.pixel(x, y) + 3, 10.0f);
  for (int y = 0; y <= 3; ++y) std::fill(shapes.pixel(11, y), shapes.pixel(11, y) + 3, 20.0f);
  for (int y = 2; y <= 3; ++y)
    for (int x = 8; x <= 9; ++x) std::fill(shapes.pixel(x, y), shapes.pixel(x, y) + 3, 20.0f);
  const Image before = shapes;
  ASSERT_EQ(kFireflyRank, 2);
  EXPECT_EQ(remove_fireflies(shapes), 0);
  EXPECT_EQ(shapes.rgb, before.rgb);
  EXPECT_THROW(remove_fireflies(shapes, 3.0, 0), Error);
  EXPECT_THROW(remove_fireflies(shapes, 3.0, 3), Error);
}

}  // namespace
}  // namespace matlas::render
