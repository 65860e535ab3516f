#include "render/label_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace matlas::render {

bool overlaps(const LabelBox& a, const LabelBox& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

std::vector<LabelPlacement> place_labels(const std::vector<LabelRequest>& labels, double width, double height,
                                         double marker_radius, double gap) {
  const std::size_t n = labels.size();
  std::vector<LabelPlacement> out(n);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return labels[a].priority > labels[b].priority; });
  // Markers are obstacles for every label but their own (as their bounding squares).
  std::vector<LabelBox> markers(n);
  for (std::size_t i = 0; i < n; ++i)
    markers[i] = {labels[i].x - marker_radius, labels[i].y - marker_radius, labels[i].x + marker_radius,
                  labels[i].y + marker_radius};
  std::vector<LabelBox> placed;
  placed.reserve(n);
  const double off = marker_radius + gap;
  for (const std::size_t i : order) {
    const LabelRequest& l = labels[i];
    const double d = 0.7 * off;  // diagonal positions: the label's corner near the marker
    const LabelBox candidates[8] = {
        {l.x + off, l.y - l.height / 2, l.x + off + l.width, l.y + l.height / 2},  // right
        {l.x - off - l.width, l.y - l.height / 2, l.x - off, l.y + l.height / 2},  // left
        {l.x - l.width / 2, l.y - off - l.height, l.x + l.width / 2, l.y - off},   // above
        {l.x - l.width / 2, l.y + off, l.x + l.width / 2, l.y + off + l.height},   // below
        {l.x + d, l.y - d - l.height, l.x + d + l.width, l.y - d},                 // above right
        {l.x + d, l.y + d, l.x + d + l.width, l.y + d + l.height},                 // below right
        {l.x - d - l.width, l.y - d - l.height, l.x - d, l.y - d},                 // above left
        {l.x - d - l.width, l.y + d, l.x - d, l.y + d + l.height},                 // below left
    };
    for (const LabelBox& c : candidates) {
      if (c.x0 < 0 || c.y0 < 0 || c.x1 > width || c.y1 > height) continue;
      bool free = std::none_of(placed.begin(), placed.end(), [&](const LabelBox& p) { return overlaps(c, p); });
      for (std::size_t k = 0; free && k < n; ++k) free = k == i || !overlaps(c, markers[k]);
      if (!free) continue;
      out[i] = {true, c};
      placed.push_back(c);
      break;
    }
  }
  return out;
}

std::vector<double> isolation(const std::vector<double>& xs, const std::vector<double>& ys) {
  const std::size_t n = std::min(xs.size(), ys.size());
  std::vector<double> d(n, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (i != j) d[i] = std::min(d[i], std::hypot(xs[i] - xs[j], ys[i] - ys[j]));
  return d;
}

}  // namespace matlas::render
