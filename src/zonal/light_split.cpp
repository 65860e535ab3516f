#include "zonal/light_split.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/check.h"
#include "core/error.h"
#include "render/sampling.h"

namespace matlas::zonal {

namespace {

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

}  // namespace

LightSplit split_lights(const render::Environment& env, const LightSplitSettings& settings) {
  if (settings.max_texels < 0 || settings.max_texels > (1 << 20) || !(settings.ratio > 0) ||
      settings.merge < 1 || settings.merge > 64)
    throw Error("light split: settings out of range");
  if (env.is_constant()) return {env, {}, 0, 0.0};
  Image map = env.map();
  const int w = map.width, h = map.height, m = settings.merge;
  // Exact solid angle of a texel of row y: (cos theta0 - cos theta1) 2 pi / w.
  auto solid_angle = [&](int y) { return (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h)) * 2.0 * kPi / w; };
  double total = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) total += luminance(map.pixel(x, y)) * solid_angle(y);
  const double threshold = settings.ratio * total / (4.0 * kPi);
  // Blocks of m x m texels (the last row and column of blocks may be smaller), by mean luminance.
  const int bw = (w + m - 1) / m, bh = (h + m - 1) / m;
  std::vector<double> lum(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh), 0.0);
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      double sum = 0.0;
      int n = 0;
      for (int y = by * m; y < std::min(h, (by + 1) * m); ++y)
        for (int x = bx * m; x < std::min(w, (bx + 1) * m); ++x, ++n) sum += luminance(map.pixel(x, y));
      lum[static_cast<std::size_t>(by) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(bx)] = sum / n;
    }
  std::vector<std::size_t> order(lum.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const std::size_t keep = std::min(order.size(), static_cast<std::size_t>(settings.max_texels));
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(keep), order.end(),
                    [&](std::size_t a, std::size_t b) { return lum[a] > lum[b]; });
  LightSplit out{env, {}, 0, 0.0};
  double moved = 0.0;
  for (std::size_t k = 0; k < keep && lum[order[k]] >= threshold && lum[order[k]] > 0; ++k) {
    const int bx = static_cast<int>(order[k] % static_cast<std::size_t>(bw)), by = static_cast<int>(order[k] / static_cast<std::size_t>(bw));
    Vec3 centre = Vec3::Zero();
    Rgb block_power = Rgb::Zero();
    for (int y = by * m; y < std::min(h, (by + 1) * m); ++y)
      for (int x = bx * m; x < std::min(w, (bx + 1) * m); ++x) {
        float* p = map.pixel(x, y);
        const Rgb radiance(p[0], p[1], p[2]);
        const double omega = solid_angle(y);
        const Vec3 d = env.from_uv((x + 0.5) / w, (y + 0.5) / h);
        if (m == 1) out.points.push_back({d, radiance * omega});
        centre += d * (luminance(p) * omega);
        block_power += radiance * omega;
        moved += luminance(p) * omega;
        p[0] = p[1] = p[2] = 0.0f;
        ++out.texels;
      }
    if (m > 1) out.points.push_back({centre.norm() > 0 ? Vec3(centre.normalized()) : env.from_uv((bx + 0.5) * m / w, (by + 0.5) * m / h), block_power});
  }
  out.light_fraction = total > 0 ? moved / total : 0.0;
  out.residual = render::Environment(std::move(map), env.rotation() * 180.0 / kPi, 1.0);
  return out;
}

Rgb shade_lights(const std::vector<LightPoint>& points, const render::Material& material, const Vec3& n,
                 const Vec3& wo) {
  Vec3 t, b;
  render::orthonormal_basis(n, t, b);
  const Vec3 wo_local(t.dot(wo), b.dot(wo), n.dot(wo));
  if (wo_local.z() <= 0) return Rgb::Zero();
  Rgb sum = Rgb::Zero();
  for (const LightPoint& p : points) {
    const double c = n.dot(p.direction);
    if (c <= 0) continue;
    const Vec3 wi_local(t.dot(p.direction), b.dot(p.direction), c);
    sum += material.eval(wi_local, wo_local) * p.power * c;
  }
  return sum;
}

}  // namespace matlas::zonal
