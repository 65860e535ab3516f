// Label declutter: no two shown labels overlap, none covers another marker or leaves the picture,
// an isolated marker always keeps its label, a crowded cluster shows only some.
#include <gtest/gtest.h>

#include <random>

#include "render/label_layout.h"

namespace matlas::render {
namespace {

TEST(LabelLayout, ShownLabelsNeverOverlapEachOtherOrMarkers) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double W = 400, H = 300, r = 4;
    std::vector<LabelRequest> labels;
    std::vector<double> xs, ys;
    // Half of the markers in a tight cluster (the collapsed-layout case), half spread out.
    for (int i = 0; i < 60; ++i) {
      const bool crowded = i % 2 == 0;
      const double x = crowded ? 200 + 20 * u(rng) : W * u(rng), y = crowded ? 150 + 20 * u(rng) : H * u(rng);
      xs.push_back(x), ys.push_back(y);
      labels.push_back({x, y, 30 + 60 * u(rng), 14, 0});
    }
    const std::vector<double> p = isolation(xs, ys);
    for (std::size_t i = 0; i < labels.size(); ++i) labels[i].priority = p[i];
    const std::vector<LabelPlacement> placed = place_labels(labels, W, H, r);
    ASSERT_EQ(placed.size(), labels.size());
    int shown = 0, crowded_shown = 0;
    for (std::size_t i = 0; i < placed.size(); ++i) {
      if (!placed[i].shown) continue;
      ++shown;
      crowded_shown += i % 2 == 0;
      const LabelBox& b = placed[i].box;
      EXPECT_GE(b.x0, 0);
      EXPECT_GE(b.y0, 0);
      EXPECT_LE(b.x1, W);
      EXPECT_LE(b.y1, H);
      EXPECT_NEAR(b.x1 - b.x0, labels[i].width, 1e-9);
      for (std::size_t j = 0; j < placed.size(); ++j) {
        if (j == i) continue;
        if (placed[j].shown && j > i) {
          EXPECT_FALSE(overlaps(b, placed[j].box)) << i << " " << j;
        }
        const LabelBox marker{labels[j].x - r, labels[j].y - r, labels[j].x + r, labels[j].y + r};
        EXPECT_FALSE(overlaps(b, marker)) << "label " << i << " covers marker " << j;
      }
    }
    EXPECT_GT(shown, 10);
    EXPECT_LT(crowded_shown, 10) << "a 20-pixel cluster of 30 markers cannot show most of its labels";
  }
}

TEST(LabelLayout, IsolatedMarkersKeepTheirLabelAndTheLayoutIsDeterministic) {
  std::vector<LabelRequest> labels = {{50, 50, 40, 12, 0}, {52, 51, 40, 12, 0}, {51, 53, 40, 12, 0}, {300, 200, 60, 12, 0}};
  const std::vector<double> p = isolation({50, 52, 51, 300}, {50, 51, 53, 200});
  for (std::size_t i = 0; i < labels.size(); ++i) labels[i].priority = p[i];
  const auto a = place_labels(labels, 400, 300, 3), b = place_labels(labels, 400, 300, 3);
  EXPECT_TRUE(a[3].shown);
  EXPECT_GT(a[3].box.x0, 300);  // first choice: right of the marker
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].shown, b[i].shown);
    EXPECT_EQ(a[i].box.x0, b[i].box.x0);
  }
  // Near the right edge the label goes to the left.
  const auto edge = place_labels({{395, 100, 40, 12, 1}}, 400, 300, 3);
  ASSERT_TRUE(edge[0].shown);
  EXPECT_LT(edge[0].box.x1, 395);
  EXPECT_FALSE(overlaps({0, 0, 1, 1}, {1, 0, 2, 1}));  // touching is not overlapping
  EXPECT_TRUE(overlaps({0, 0, 1, 1}, {0.5, 0.5, 2, 2}));
}

}  // namespace
}  // namespace matlas::render
