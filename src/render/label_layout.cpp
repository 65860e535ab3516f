#include "render/label_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace matlas::render {

namespace {

/// Boxes bucketed by the cells of a uniform grid over [0, width] x [0, height] that they overlap
/// (boxes reaching outside are clamped to the border cells): a query tests only the boxes of the
/// cells its box overlaps, so placing n labels among n markers costs about n tests per label's
/// neighbourhood instead of n^2 in all. Exact: the grid only skips boxes that cannot overlap.
class BoxGrid {
public:
  BoxGrid(double width, double height) {
    // About 32-pixel cells, at most 256 per side (a huge canvas gets coarser cells, never more memory).
    cols_ = cells_for(width);
    rows_ = cells_for(height);
    sx_ = width > 0 ? cols_ / width : 0.0;
    sy_ = height > 0 ? rows_ / height : 0.0;
    cells_.resize(static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_));
  }

  void insert(const LabelBox& b, std::size_t id) {
    const Range r = range(b);
    for (int j = r.j0; j <= r.j1; ++j)
      for (int i = r.i0; i <= r.i1; ++i) cells_[index(i, j)].push_back(id);
  }

  /// Whether `b` overlaps a stored box other than `skip`, boxes[] holding them by id.
  bool overlaps_any(const LabelBox& b, const std::vector<LabelBox>& boxes,
                    std::size_t skip = std::numeric_limits<std::size_t>::max()) const {
    const Range r = range(b);
    for (int j = r.j0; j <= r.j1; ++j)
      for (int i = r.i0; i <= r.i1; ++i)
        for (const std::size_t k : cells_[index(i, j)])
          if (k != skip && overlaps(b, boxes[k])) return true;
    return false;
  }

private:
  struct Range {
    int i0, i1, j0, j1;
  };
  static int cells_for(double extent) {
    if (!(extent > 0)) return 1;
    return static_cast<int>(std::clamp(std::ceil(extent / 32.0), 1.0, 256.0));
  }
  static int cell(double v, double scale, int count) {
    const double c = std::floor(v * scale);
    if (!(c > 0)) return 0;  // also NaN
    return c >= count - 1 ? count - 1 : static_cast<int>(c);
  }
  Range range(const LabelBox& b) const {
    return {cell(b.x0, sx_, cols_), cell(b.x1, sx_, cols_), cell(b.y0, sy_, rows_), cell(b.y1, sy_, rows_)};
  }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(i);
  }

  int cols_ = 1, rows_ = 1;
  double sx_ = 0, sy_ = 0;
  std::vector<std::vector<std::size_t>> cells_;
};

}  // namespace

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
  BoxGrid marker_grid(width, height), label_grid(width, height);
  for (std::size_t i = 0; i < n; ++i) {
    markers[i] = {labels[i].x - marker_radius, labels[i].y - marker_radius, labels[i].x + marker_radius,
                  labels[i].y + marker_radius};
    marker_grid.insert(markers[i], i);
  }
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
      if (label_grid.overlaps_any(c, placed) || marker_grid.overlaps_any(c, markers, i)) continue;
      out[i] = {true, c};
      label_grid.insert(c, placed.size());
      placed.push_back(c);
      break;
    }
  }
  return out;
}

std::vector<double> isolation(const std::vector<double>& xs, const std::vector<double>& ys) {
  // Sweep in x order: from each point, walk left and right until the x gap alone exceeds the
  // nearest distance found (about n sqrt(n) distances for points spread over a plane, not n^2).
  const std::size_t n = std::min(xs.size(), ys.size());
  std::vector<double> d(n, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  // NaN coordinates last (they are nobody's neighbour, as std::min over their NaN distances leaves them).
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::isnan(xs[b]) ? !std::isnan(xs[a]) : xs[a] < xs[b];
  });
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t i = order[s];
    double best = d[i];
    for (std::size_t t = s + 1; t < n && xs[order[t]] - xs[i] < best; ++t)
      best = std::min(best, std::hypot(xs[i] - xs[order[t]], ys[i] - ys[order[t]]));
    for (std::size_t t = s; t-- > 0 && xs[i] - xs[order[t]] < best;)
      best = std::min(best, std::hypot(xs[i] - xs[order[t]], ys[i] - ys[order[t]]));
    d[i] = best;
  }
  return d;
}

}  // namespace matlas::render
