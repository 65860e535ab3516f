#pragma once
// Label placement for maps: greedy decluttering. Labels are considered in priority order (by
// default the most isolated material first, so that a crowded cluster shows one or two names and
// every isolated material keeps its own); each tries eight positions around its marker (right,
// left, above, below, then the four diagonals) and takes the first whose box overlaps no label already placed, no other
// marker, and stays inside the picture. Labels that fit nowhere are hidden (the browser shows
// them on hover and when zooming in spreads the markers apart). The browser's web/src/labels.ts
// is the same algorithm.
#include <vector>

namespace matlas::render {

struct LabelBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< pixels, x0 <= x1, y0 <= y1
};

/// Whether two boxes share interior (touching edges do not overlap).
bool overlaps(const LabelBox& a, const LabelBox& b);

struct LabelRequest {
  double x = 0, y = 0;           ///< the marker's centre
  double width = 0, height = 0;  ///< the label's size
  double priority = 0;           ///< larger first
};

struct LabelPlacement {
  bool shown = false;
  LabelBox box;  ///< where the label goes (meaningful when shown)
};

/// Greedy placement (see above) inside [0, width] x [0, height]; markers are discs of radius
/// `marker_radius`, labels sit `gap` pixels from them. Deterministic: ties in priority keep the
/// input order.
std::vector<LabelPlacement> place_labels(const std::vector<LabelRequest>& labels, double width, double height,
                                         double marker_radius, double gap = 3.0);

/// A priority for each point: its distance to the nearest other point (isolated first).
std::vector<double> isolation(const std::vector<double>& xs, const std::vector<double>& ys);

}  // namespace matlas::render
