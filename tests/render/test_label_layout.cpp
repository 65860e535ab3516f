// Label declutter: no two shown labels overlap, none covers another marker or leaves the picture,
// an isolated marker always keeps its label, a crowded cluster shows only some; the grid-bucketed
// placement and the sweep for isolation give exactly what the all-pairs definitions give.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "render/label_layout.h"

namespace matlas::render {
namespace {

/// The definitions, all pairs (O(n^2)): what place_labels and isolation must reproduce exactly.
std::vector<LabelPlacement> place_labels_all_pairs(const std::vector<LabelRequest>& labels, double width, double height,
                                                   double marker_radius, double gap = 3.0) {
  const std::size_t n = labels.size();
  std::vector<LabelPlacement> out(n);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return labels[a].priority > labels[b].priority; });
  std::vector<LabelBox> placed;
  const double off = marker_radius + gap, d = 0.7 * off;
  for (const std::size_t i : order) {
    const LabelRequest& l = labels[i];
    const LabelBox candidates[8] = {
        {l.x + off, l.y - l.height / 2, l.x + off + l.width, l.y + l.height / 2},
        {l.x - off - l.width, l.y - l.height / 2, l.x - off, l.y + l.height / 2},
        {l.x - l.width / 2, l.y - off - l.height, l.x + l.width / 2, l.y - off},
        {l.x - l.width / 2, l.y + off, l.x + l.width / 2, l.y + off + l.height},
        {l.x + d, l.y - d - l.height, l.x + d + l.width, l.y - d},
        {l.x + d, l.y + d, l.x + d + l.width, l.y + d + l.height},
        {l.x - d - l.width, l.y - d - l.height, l.x - d, l.y - d},
        {l.x - d - l.width, l.y + d, l.x - d, l.y + d + l.height},
    };
    for (const LabelBox& c : candidates) {
      if (c.x0 < 0 || c.y0 < 0 || c.x1 > width || c.y1 > height) continue;
      bool free = std::none_of(placed.begin(), placed.end(), [&](const LabelBox& p) { return overlaps(c, p); });
      for (std::size_t k = 0; free && k < n; ++k)
        free = k == i || !overlaps(c, {labels[k].x - marker_radius, labels[k].y - marker_radius,
                                       labels[k].x + marker_radius, labels[k].y + marker_radius});
      if (!free) continue;
      out[i] = {true, c};
      placed.push_back(c);
      break;
    }
  }
  return out;
}

std::vector<double> isolation_all_pairs(const std::vector<double>& xs, const std::vector<double>& ys) {
  std::vector<double> d(xs.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < xs.size(); ++i)
    for (std::size_t j = 0; j < xs.size(); ++j)
      if (i != j) d[i] = std::min(d[i], std::hypot(xs[i] - xs[j], ys[i] - ys[j]));
  return d;
}

TEST(LabelLayout, EqualsTheAllPairsDefinitionForAThousandMarkers) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const int n : {0, 1, 2, 50, 1000}) {
    const double W = 900, H = 640, r = 7;
    std::vector<LabelRequest> labels;
    std::vector<double> xs, ys;
    for (int i = 0; i < n; ++i) {
      // Clusters, a spread, markers a little outside the canvas (the browser keeps those within 8 px),
      // and repeated points.
      const int kind = i % 4;
      double x = kind == 0 ? 300 + 30 * u(rng) : -8 + (W + 16) * u(rng);
      double y = kind == 0 ? 200 + 30 * u(rng) : -8 + (H + 16) * u(rng);
      if (kind == 3 && i > 4) x = xs[static_cast<std::size_t>(i - 4)], y = ys[static_cast<std::size_t>(i - 4)];
      xs.push_back(x), ys.push_back(y);
      labels.push_back({x, y, 20 + 140 * u(rng), 15, 0});
    }
    const std::vector<double> p = isolation(xs, ys), q = isolation_all_pairs(xs, ys);
    ASSERT_EQ(p.size(), q.size());
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p[i], q[i]) << "point " << i << " of " << n;
    for (std::size_t i = 0; i < labels.size(); ++i) labels[i].priority = p[i];
    const std::vector<LabelPlacement> a = place_labels(labels, W, H, r), b = place_labels_all_pairs(labels, W, H, r);
    ASSERT_EQ(a.size(), b.size());
    int shown = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].shown, b[i].shown) << "label " << i << " of " << n;
      shown += a[i].shown;
      if (!a[i].shown) continue;
      EXPECT_EQ(a[i].box.x0, b[i].box.x0);
      EXPECT_EQ(a[i].box.y0, b[i].box.y0);
      EXPECT_EQ(a[i].box.x1, b[i].box.x1);
      EXPECT_EQ(a[i].box.y1, b[i].box.y1);
    }
    if (n >= 50) {
      EXPECT_GT(shown, n / 20) << n;
    }
  }
}

TEST(LabelLayout, IsolationIgnoresNanPointsAsTheDefinitionDoes) {
  const std::vector<double> xs = {0, 3, std::nan(""), 10, 10}, ys = {0, 4, 1, 0, std::nan("")};
  const std::vector<double> p = isolation(xs, ys), q = isolation_all_pairs(xs, ys);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p[i], q[i]) << i;
  EXPECT_EQ(p[0], 5.0);
  EXPECT_TRUE(std::isinf(p[2]));
}

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
