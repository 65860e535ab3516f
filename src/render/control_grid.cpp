#include "render/control_grid.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/parallel.h"

namespace matlas::render {

ControlGrid control_grid(const Scene& scene, int width, int height, const ControlVariate& control,
                         ProgressSink& progress) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error("control grid size must be between 1 and 16384 pixels, got " + std::to_string(width) + "x" +
                std::to_string(height));
  ControlGrid grid;
  grid.width = width;
  grid.height = height;
  const std::size_t w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
  // The pixel corners' view cosines (-1: the corner misses the object) and normals.
  std::vector<double> corner_cos((w + 1) * (h + 1), -1.0);
  std::vector<Vec3> corner_normal((w + 1) * (h + 1), Vec3::Zero());
  parallel_for(0, h + 1, [&](std::size_t y0, std::size_t y1) {
    Vec3 o, d;
    for (std::size_t y = y0; y < y1; ++y)
      for (std::size_t x = 0; x <= w; ++x) {
        scene.camera_ray(static_cast<double>(x), static_cast<double>(y), width, height, &o, &d);
        const std::optional<Hit> hit = scene.intersect(o, d);
        if (!hit || !hit->object) continue;
        corner_cos[y * (w + 1) + x] = -hit->normal.dot(d);
        corner_normal[y * (w + 1) + x] = hit->normal;
      }
  });
  // Each pixel's subdivisions: 1 where its corners see the object at cos >= kControlGridCosine
  // and their normals lie within kControlGridAngle; more as the view grazes or the normal turns
  // faster; none where a corner misses the object or the normals turn more than
  // kControlGridMaxSubdivisions cells can follow (a crease, an edge in front of another surface).
  grid.cells.resize(w * h);
  std::size_t total = 0;
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      const std::size_t corners[4] = {y * (w + 1) + x, y * (w + 1) + x + 1, (y + 1) * (w + 1) + x, (y + 1) * (w + 1) + x + 1};
      double c = 1.0, dot = 1.0;
      for (int i = 0; i < 4; ++i) {
        c = std::min(c, corner_cos[corners[i]]);
        for (int j = i + 1; j < 4; ++j) dot = std::min(dot, corner_normal[corners[i]].dot(corner_normal[corners[j]]));
      }
      ControlGrid::Cell& cell = grid.cells[y * w + x];
      if (!(c > 0)) continue;
      const double turn = std::acos(std::clamp(dot, -1.0, 1.0));
      const int s = std::max(static_cast<int>(std::ceil(kControlGridCosine / std::min(c, kControlGridCosine) - 1e-9)),
                             static_cast<int>(std::ceil(turn / kControlGridAngle - 1e-9)));
      if (s > kControlGridMaxSubdivisions) continue;
      cell.subdivisions = std::max(1, s);
      cell.offset = total;
      total += static_cast<std::size_t>(cell.subdivisions + 1) * static_cast<std::size_t>(cell.subdivisions + 1);
    }
  grid.values.assign(total, Rgb::Zero());
  // The pixel corners' values once (a one-cell pixel shares each with three neighbours), then
  // each cut pixel's inner points; the corners' rays are the cells' own (x + s / s is x + 1).
  std::vector<Rgb> corner_value((w + 1) * (h + 1), Rgb::Zero());
  std::mutex progress_mutex;
  std::atomic<std::uint64_t> rows_done{0};
  const auto report = [&] {  // before a row: a throwing sink stops the grid early
    const std::uint64_t done = rows_done++;
    std::lock_guard lock(progress_mutex);
    progress.update("control grid", done, 2 * h + 1);
  };
  progress.update("control grid", 0, 2 * h + 1);
  parallel_for_each(0, h + 1, [&](std::size_t y) {
    report();
    Vec3 o, d;
    for (std::size_t x = 0; x <= w; ++x) {
      if (!(corner_cos[y * (w + 1) + x] > 0)) continue;
      scene.camera_ray(static_cast<double>(x), static_cast<double>(y), width, height, &o, &d);
      corner_value[y * (w + 1) + x] = control.smooth_integral(corner_normal[y * (w + 1) + x], -d);
    }
  });
  parallel_for_each(0, h, [&](std::size_t y) {
    report();
    Vec3 o, d;
    for (std::size_t x = 0; x < w; ++x) {
      ControlGrid::Cell& cell = grid.cells[y * w + x];
      const int s = cell.subdivisions;
      for (int j = 0; j <= s && cell.subdivisions > 0; ++j)
        for (int i = 0; i <= s; ++i) {
          Rgb& value = grid.values[cell.offset + static_cast<std::size_t>(j) * static_cast<std::size_t>(s + 1) + static_cast<std::size_t>(i)];
          if ((i == 0 || i == s) && (j == 0 || j == s)) {
            value = corner_value[(y + static_cast<std::size_t>(j / s)) * (w + 1) + x + static_cast<std::size_t>(i / s)];
            continue;
          }
          scene.camera_ray(static_cast<double>(x) + static_cast<double>(i) / s, static_cast<double>(y) + static_cast<double>(j) / s,
                           width, height, &o, &d);
          const std::optional<Hit> hit = scene.intersect(o, d);
          if (!hit || !hit->object || !(-hit->normal.dot(d) > 0)) {
            cell.subdivisions = 0;  // a point between the corners misses it (a concave silhouette)
            break;
          }
          value = control.smooth_integral(hit->normal, -d);
        }
    }
  });
  progress.finish("control grid");
  return grid;
}

}  // namespace matlas::render
