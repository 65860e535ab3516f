#include "render/latent_map.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/error.h"
#include "core/parallel.h"
#include "manifold/model.h"
#include "render/image_basis.h"
#include "render/text.h"

namespace matlas::render {

namespace {

void extent(const Model& model, LatentPlane& plane, double margin) {
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (int i = 0; i < model.count(); ++i) {
    const Eigen::Vector2d p = plane.project(model.latent().row(i).transpose());
    u0 = std::min(u0, p.x()), u1 = std::max(u1, p.x()), v0 = std::min(v0, p.y()), v1 = std::max(v1, p.y());
  }
  double side = std::max({u1 - u0, v1 - v0, 1e-6});
  // Square picture: centre the shorter side.
  const double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
  side *= 1.0 + 2.0 * margin;
  plane.u_min = cu - 0.5 * side, plane.u_max = cu + 0.5 * side;
  plane.v_min = cv - 0.5 * side, plane.v_max = cv + 0.5 * side;
}

void check_at(const Model& model, const Eigen::VectorXd& at) {
  if (at.size() != model.dim())
    throw Error("latent map: the fixed point has " + std::to_string(at.size()) + " coordinates, the model q = " +
                std::to_string(model.dim()));
}

Eigen::Array3d lerp(const Eigen::Array3d& a, const Eigen::Array3d& b, double t) { return a + (b - a) * t; }

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

LatentPlane LatentPlane::from_dims(const Model& model, int d0, int d1, const Eigen::VectorXd& at, double margin) {
  const int q = model.dim();
  if (d0 < 0 || d0 >= q || d1 < 0 || d1 >= q || d0 == d1)
    throw Error("latent map: --dims must be two different dimensions in 0.." + std::to_string(q - 1));
  check_at(model, at);
  LatentPlane p;
  p.origin = at;
  p.origin[d0] = 0, p.origin[d1] = 0;
  p.axis_u = Eigen::VectorXd::Unit(q, d0);
  p.axis_v = Eigen::VectorXd::Unit(q, d1);
  extent(model, p, margin);
  return p;
}

LatentPlane LatentPlane::pca(const Model& model, const Eigen::VectorXd& at, double margin) {
  const int q = model.dim();
  check_at(model, at);
  if (q < 2) return automatic(model, margin);
  const Eigen::MatrixXd centred = model.latent().rowwise() - model.latent().colwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(centred.transpose() * centred);
  LatentPlane p;
  p.axis_u = eig.eigenvectors().col(q - 1);
  p.axis_v = eig.eigenvectors().col(q - 2);
  // Origin: `at` with its components along the plane removed (u, v = 0 is the projection of 0).
  p.origin = at - at.dot(p.axis_u) * p.axis_u - at.dot(p.axis_v) * p.axis_v;
  extent(model, p, margin);
  return p;
}

LatentPlane LatentPlane::automatic(const Model& model, double margin) {
  const Eigen::VectorXd mean = model.latent().colwise().mean().transpose();
  if (model.dim() >= 2) return from_dims(model, 0, 1, mean, margin);
  LatentPlane p;
  p.origin = Eigen::VectorXd::Zero(1);
  p.axis_u = Eigen::VectorXd::Unit(1, 0);
  p.axis_v = Eigen::VectorXd::Zero(1);
  extent(model, p, margin);
  return p;
}

LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows) {
  if (cols <= 0 || rows <= 0) throw Error("latent map: grid size must be positive");
  LatentGrid g;
  g.cols = cols, g.rows = rows;
  g.points.resize(static_cast<Eigen::Index>(cols) * rows, model.dim());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double u = plane.u_min + (c + 0.5) / cols * (plane.u_max - plane.u_min);
      const double v = plane.v_max - (r + 0.5) / rows * (plane.v_max - plane.v_min);
      g.points.row(static_cast<Eigen::Index>(r) * cols + c) = plane.point(u, v).transpose();
    }
  g.weights = model.predict_batch(g.points).weights;
  return g;
}

Eigen::Array3d colour_map(double t) {
  // Viridis at 5 stops (sRGB), linearised.
  static const double stops[5][3] = {{0.267, 0.005, 0.329}, {0.229, 0.322, 0.546}, {0.128, 0.567, 0.551},
                                     {0.369, 0.789, 0.383}, {0.993, 0.906, 0.144}};
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(static_cast<int>(t), 3);
  Eigen::Array3d c = lerp(Eigen::Array3d(stops[i][0], stops[i][1], stops[i][2]),
                          Eigen::Array3d(stops[i + 1][0], stops[i + 1][1], stops[i + 1][2]), t - i);
  for (int k = 0; k < 3; ++k) c[k] = srgb_decode(static_cast<float>(c[k]));
  return c;
}

Image render_latent_map(const Model& model, const LatentPlane& plane, const MapOptions& o, ProgressSink& progress) {
  if (o.size < 16 || o.size > 8192) throw Error("latent map: size must be in 16..8192");
  Image map(o.size, o.size);
  if (o.layer == MapLayer::image) {
    if (!o.basis) throw Error("latent map: the image layer needs an image basis (--basis)");
    if (o.basis->count() != model.count())
      throw Error("latent map: the basis has " + std::to_string(o.basis->count()) + " materials, the model " +
                  std::to_string(model.count()));
    const int k = std::max(1, o.thumbnails);
    const LatentGrid g = latent_grid(model, plane, k, k);
    ProgressTask task(progress, "thumbnails", static_cast<std::uint64_t>(k) * k);
    Image thumb(o.basis->width(), o.basis->height());
    for (int cell = 0; cell < k * k; ++cell) {
      o.basis->compose(g.weights.col(cell), thumb.rgb.data());
      const int cx = cell % k, cy = cell / k;
      const int x0 = cx * o.size / k, x1 = (cx + 1) * o.size / k, y0 = cy * o.size / k, y1 = (cy + 1) * o.size / k;
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
          for (int c = 0; c < 3; ++c) {
            const float v = static_cast<float>(sum[c] / area);
            map.pixel(x, y)[c] = srgb_decode(tone_map_to_srgb8(v, {ToneMap::Curve::aces, 0.0}) / 255.0f);
          }
        }
      task.advance();
    }
  } else {
    const int cells = std::max(2, o.cells);
    const LatentGrid g = latent_grid(model, plane, cells, cells);
    std::vector<Eigen::Array3d> colour(static_cast<std::size_t>(cells) * cells);
    parallel_for(0, colour.size(), [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) {
        const auto idx = static_cast<Eigen::Index>(i);
        if (o.layer == MapLayer::albedo) {
          const Rgb a = model.albedo_curve(g.weights.col(idx)).front();
          colour[i] = (a * o.albedo_gain).max(0.0).min(1.0);
        } else {
          colour[i] = colour_map(model.variance(g.points.row(idx).transpose()));
        }
      }
    });
    for (int y = 0; y < o.size; ++y)
      for (int x = 0; x < o.size; ++x) {
        const auto& c = colour[static_cast<std::size_t>(y * cells / o.size) * cells + static_cast<std::size_t>(x * cells / o.size)];
        for (int k = 0; k < 3; ++k) map.pixel(x, y)[k] = static_cast<float>(c[k]);
      }
  }
  // Materials: a marker at each projected point, and the name beside it.
  const float text_size = std::max(10.0f, static_cast<float>(o.size) / 70.0f);
  for (int i = 0; i < model.count(); ++i) {
    const Eigen::Vector2d p = plane.project(model.latent().row(i).transpose());
    const double px = (p.x() - plane.u_min) / (plane.u_max - plane.u_min) * o.size;
    const double py = plane.v_max > plane.v_min ? (plane.v_max - p.y()) / (plane.v_max - plane.v_min) * o.size : 0.5 * o.size;
    draw_marker(map, px, py, std::max(3.0, o.size / 160.0));
    if (o.labels)
      draw_text(map, static_cast<int>(px) + 6, static_cast<int>(py) - static_cast<int>(text_size / 2),
                model.names()[static_cast<std::size_t>(i)], text_size, Rgb::Constant(1.0));
  }
  return map;
}

}  // namespace matlas::render
