#include "atlas/latent_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/error.h"
#include "render/text.h"

namespace matlas::atlas {

using render::draw_text;
using render::isolation;
using render::LabelRequest;
using render::place_labels;
using render::LabelPlacement;
using render::text_width;

namespace {

void draw_marker(Image& im, double cx, double cy, double r) {
  for (int y = static_cast<int>(cy - r - 2); y <= static_cast<int>(cy + r + 2); ++y)
    for (int x = static_cast<int>(cx - r - 2); x <= static_cast<int>(cx + r + 2); ++x) {
      if (x < 0 || y < 0 || x >= im.width || y >= im.height) continue;
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      float* p = im.pixel(x, y);
      if (d <= r - 1.5) {
        for (int k = 0; k < 3; ++k) p[k] = 1.0f;
      } else if (d <= r + 0.5) {
        for (int k = 0; k < 3; ++k) p[k] = 0.0f;
      }
    }
}

}  // namespace

std::pair<int, int> map_size(const LatentPlane& plane, int size) {
  const double du = plane.u_max - plane.u_min, dv = plane.v_max - plane.v_min;
  if (!(du > 0) || !(dv > 0)) return {size, size};
  if (du >= dv) return {size, std::max(16, static_cast<int>(std::lround(size * dv / du)))};
  return {std::max(16, static_cast<int>(std::lround(size * du / dv))), size};
}

int MapLabels::shown() const {
  return static_cast<int>(std::count_if(labels.begin(), labels.end(), [](const LabelPlacement& l) { return l.shown; }));
}

MapLabels map_labels(const Model& model, const LatentPlane& plane, int width, int height, float text_size,
                     double marker_radius) {
  MapLabels out;
  const int n = model.count();
  std::vector<double> xs, ys;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = plane.project(model.latent().row(i).transpose());
    const double px = (p.x() - plane.u_min) / (plane.u_max - plane.u_min) * width;
    const double py = plane.v_max > plane.v_min ? (plane.v_max - p.y()) / (plane.v_max - plane.v_min) * height : 0.5 * height;
    out.markers.emplace_back(px, py);
    xs.push_back(px), ys.push_back(py);
  }
  const std::vector<double> priority = isolation(xs, ys);
  std::vector<LabelRequest> requests;
  // draw_text's bitmap is text_size + 2 pixels tall and text_width + 2 wide, plus a 1-pixel outline.
  const double label_height = std::ceil(text_size) + 4;
  for (int i = 0; i < n; ++i) {
    const auto s = static_cast<std::size_t>(i);
    requests.push_back({xs[s], ys[s], static_cast<double>(text_width(model.names()[s], text_size) + 4), label_height,
                        priority[s]});
  }
  out.labels = place_labels(requests, width, height, marker_radius);
  return out;
}

namespace {

float label_text_size(int longer) { return std::max(10.0f, static_cast<float>(longer) / 70.0f); }
double marker_radius(int longer) { return std::max(3.0, longer / 160.0); }

}  // namespace

MapLabels map_labels(const Model& model, const LatentPlane& plane, const MapOptions& o) {
  const auto [mw, mh] = map_size(plane, o.size);
  const int longer = std::max(mw, mh);
  return map_labels(model, plane, mw, mh, label_text_size(longer), marker_radius(longer) + 1);
}

namespace {

/// The legend strip: what the background means, including the "no data" hatch, and on a second
/// row (`rows` = 2) how many labels were left out.
void draw_legend(Image& im, int y0, int rows, const MapOptions& o, Interpolation mode, bool fades,
                 bool plausible_everywhere, int labels_shown, int labels_total, int outside) {
  const int w = im.width;
  for (int y = y0; y < im.height; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) im.pixel(x, y)[c] = 0.008f;
  if (!render::text_available()) return;
  const int h = (im.height - y0) / rows;
  const float ts = std::max(10.0f, static_cast<float>(h) * 0.42f);
  const int pad = std::max(4, h / 5);
  const int bar_w = std::clamp(w / 5, 40, 200), bar_h = std::max(6, h / 3);
  const int by = y0 + (h - bar_h) / 2;
  const int ty = y0 + (h - static_cast<int>(ts) - 2) / 2;
  int x = pad;
  const Rgb white = Rgb::Constant(0.85);
  if (o.layer == MapLayer::variance) {
    draw_text(im, x, ty, "variance 0 (at the data)", ts, white);
    x += text_width("variance 0 (at the data)", ts) + pad;
    for (int bx = 0; bx < bar_w; ++bx) {
      const Eigen::Array3d c = colour_map(static_cast<double>(bx) / (bar_w - 1));
      for (int y = by; y < by + bar_h; ++y)
        for (int k = 0; k < 3; ++k) im.pixel(x + bx, y)[k] = static_cast<float>(c[k]);
    }
    x += bar_w + pad;
    draw_text(im, x, ty, "1 (far from the data)", ts, white);
  } else {
    if (o.layer == MapLayer::plausibility && plausible_everywhere) {
      draw_text(im, x, ty, "all plausible (a convex mix of plausible materials);", ts, white);
      x += text_width("all plausible (a convex mix of plausible materials);", ts) + pad;
    } else if (o.layer == MapLayer::plausibility) {
      draw_text(im, x, ty, "dimmed albedo: plausible;", ts, white);
      x += text_width("dimmed albedo: plausible;", ts) + pad;
      const Eigen::Array3d red = implausible_colour();
      for (int y = by; y < by + bar_h; ++y)
        for (int bx = 0; bx < bar_h; ++bx)
          for (int k = 0; k < 3; ++k) im.pixel(x + bx, y)[k] = static_cast<float>(red[k]);
      x += bar_h + pad;
      const char* what = fades ? "not plausible;" : "not plausible (negative values or albedo outside [0, 1])";
      draw_text(im, x, ty, what, ts, white);
      x += text_width(what, ts) + pad;
    }
    if (fades) {
      // A bar from a material colour to the hatch, with the variance thresholds.
      char from[48], to[96];
      std::snprintf(from, sizeof from, "variance %.2g", o.style.fade_from);
      std::snprintf(to, sizeof to, "%.2g: no data here (%s)", o.style.fade_to, far_from_data(mode));
      draw_text(im, x, ty, from, ts, white);
      x += text_width(from, ts) + pad;
      const Eigen::Array3d sample(0.45, 0.25, 0.12);
      for (int bx = 0; bx < bar_w; ++bx) {
        const double f = uncertainty_fade(o.style.fade_from + (o.style.fade_to - o.style.fade_from) * bx / (bar_w - 1.0), o.style.fade_from, o.style.fade_to);
        for (int y = by; y < by + bar_h; ++y) {
          const Eigen::Array3d c = (1 - f) * sample + f * unknown_colour(x + bx, y);
          for (int k = 0; k < 3; ++k) im.pixel(x + bx, y)[k] = static_cast<float>(c[k]);
        }
      }
      x += bar_w + pad;
      draw_text(im, x, ty, to, ts, white);
    }
  }
  if (rows > 1) {
    std::string note;
    if (outside > 0) note = std::to_string(outside) + " of " + std::to_string(labels_total) + " materials outside the frame";
    if (o.labels && labels_shown < labels_total - outside)
      note += (note.empty() ? "" : "; ") + std::to_string(labels_total - outside - labels_shown) + " of " +
              std::to_string(labels_total - outside) + " labels left out where they would overlap";
    draw_text(im, pad, ty + h, note, ts, Rgb::Constant(0.6));
  }
}

}  // namespace

Image render_latent_map(const Model& model, const LatentPlane& plane, const MapOptions& o, ProgressSink& progress) {
  if (o.size < 16 || o.size > 8192) throw Error("latent map: size must be in 16..8192");
  const auto [mw, mh] = map_size(plane, o.size);
  const MapLabels labels = map_labels(model, plane, o);
  int outside = 0;
  for (const Eigen::Vector2d& m : labels.markers) outside += m.x() < 0 || m.y() < 0 || m.x() > mw || m.y() > mh;
  const int legend_rows = outside > 0 || (o.labels && labels.shown() < model.count() - outside) ? 2 : 1;
  const int legend_h = o.legend ? legend_rows * std::max(22, o.size / 28) : 0;
  Image map(mw, mh + legend_h);
  const int longer = std::max(mw, mh);
  std::optional<PlausibilityProbe> probe;
  if (o.layer == MapLayer::plausibility) probe.emplace(model, 256);
  const bool plausible_everywhere = plausible_by_construction(model, probe ? &*probe : nullptr);
  if (o.layer == MapLayer::image) {
    if (!o.basis) throw Error("latent map: the image layer needs an image basis (--basis)");
    if (o.basis->count() != model.count())
      throw Error("latent map: the basis has " + std::to_string(o.basis->count()) + " materials, the model " +
                  std::to_string(model.count()));
    const int k = std::max(1, o.thumbnails);
    const int kx = std::max(1, static_cast<int>(std::lround(static_cast<double>(k) * mw / longer)));
    const int ky = std::max(1, static_cast<int>(std::lround(static_cast<double>(k) * mh / longer)));
    const LatentGrid g = latent_grid(model, plane, kx, ky);
    ProgressTask task(progress, "thumbnails", static_cast<std::uint64_t>(kx) * ky);
    Image thumb(o.basis->width(), o.basis->height());
    for (int cell = 0; cell < kx * ky; ++cell) {
      o.basis->compose(g.weights.col(cell), thumb.rgb.data());
      const double fade = uncertainty_fade(g.variance[cell], o.style.fade_from, o.style.fade_to);
      const int cx = cell % kx, cy = cell / kx;
      const int x0 = cx * mw / kx, x1 = (cx + 1) * mw / kx, y0 = cy * mh / ky, y1 = (cy + 1) * mh / ky;
      // Box-filter the basis image into the cell, tone mapped (ACES) back to linear for display.
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const int sx0 = (x - x0) * thumb.width / (x1 - x0), sx1 = std::max(sx0 + 1, (x - x0 + 1) * thumb.width / (x1 - x0));
          const int sy0 = (y - y0) * thumb.height / (y1 - y0), sy1 = std::max(sy0 + 1, (y - y0 + 1) * thumb.height / (y1 - y0));
          double sum[3] = {0, 0, 0};
          for (int sy = sy0; sy < sy1; ++sy)
            for (int sx = sx0; sx < sx1; ++sx)
              for (int c = 0; c < 3; ++c) sum[c] += thumb.pixel(sx, sy)[c];
          const double area = static_cast<double>((sx1 - sx0) * (sy1 - sy0));
          const Eigen::Array3d unknown = unknown_colour(x, y);
          for (int c = 0; c < 3; ++c) {
            const float v = static_cast<float>(sum[c] / area);
            const double shown = srgb_decode(tone_map_to_srgb8(v, {ToneMap::Curve::aces, 0.0}) / 255.0f);
            map.pixel(x, y)[c] = static_cast<float>((1 - fade) * shown + fade * unknown[c]);
          }
        }
      task.advance();
    }
  } else {
    const int cells = std::max(2, o.cells);
    const int cx = std::max(2, static_cast<int>(std::lround(static_cast<double>(cells) * mw / longer)));
    const int cy = std::max(2, static_cast<int>(std::lround(static_cast<double>(cells) * mh / longer)));
    const LatentGrid g = latent_grid(model, plane, cx, cy, layer_interpolation(model, o.layer),
                                     layer_projected_below(model, o.layer, o.style));
    const LayerCells layer = layer_cells(model, g, o.layer, o.style, probe ? &*probe : nullptr);
    const std::vector<Eigen::Array3d>& colour = layer.colour;
    const std::vector<double>& fade = layer.fade;
    for (int y = 0; y < mh; ++y)
      for (int x = 0; x < mw; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y * cy / mh) * cx + static_cast<std::size_t>(x * cx / mw);
        const Eigen::Array3d c = (1 - fade[cell]) * colour[cell] + fade[cell] * unknown_colour(x, y);
        for (int k = 0; k < 3; ++k) map.pixel(x, y)[k] = static_cast<float>(c[k]);
      }
  }
  // Materials: a marker at each projected point; the names that fit without overlapping.
  const float text_size = label_text_size(longer);
  const double radius = marker_radius(longer);
  for (int i = 0; i < model.count(); ++i) {
    const auto s = static_cast<std::size_t>(i);
    draw_marker(map, labels.markers[s].x(), labels.markers[s].y(), radius);
  }
  if (o.labels)
    for (int i = 0; i < model.count(); ++i) {
      const LabelPlacement& l = labels.labels[static_cast<std::size_t>(i)];
      if (l.shown)
        draw_text(map, static_cast<int>(std::lround(l.box.x0)) + 1, static_cast<int>(std::lround(l.box.y0)) + 1, model.names()[static_cast<std::size_t>(i)],
                  text_size, Rgb::Constant(1.0));
    }
  if (o.legend) draw_legend(map, mh, legend_rows, o, model.interpolation(), layer_fades(model, o.layer),
                           plausible_everywhere, labels.shown(), model.count(), outside);
  return map;
}

}  // namespace matlas::atlas
