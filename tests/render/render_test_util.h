#pragma once
// Helpers shared by the render tests: small synthetic environment maps and scenes.
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "formats/image_io.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas::test {

/// A 32 x 16 lat-long map: a sky gradient plus a bright warm "sun" patch.
inline Image synthetic_environment() {
  Image map(32, 16);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      float* p = map.pixel(x, y);
      const float t = 1.0f - static_cast<float>(y) / static_cast<float>(map.height);
      p[0] = 0.2f + 0.3f * t;
      p[1] = 0.25f + 0.4f * t;
      p[2] = 0.3f + 0.6f * t;
      if (y >= 3 && y <= 4 && x >= 20 && x <= 21) p[0] = 30.0f, p[1] = 25.0f, p[2] = 20.0f;
    }
  return map;
}

/// The previews' scene under synthetic_environment() (its sun makes glossy materials noisy).
inline std::shared_ptr<const render::Scene> sky_scene() {
  return std::make_shared<const render::Scene>(render::SceneDescription{}, std::nullopt,
                                               render::Environment(synthetic_environment()));
}

/// RMS over the `object` pixels and channels of (a - b), relative to b's RMS there (the
/// refinement's error measure, render/refinement.h).
inline double object_relative_rms(const Image& a, const Image& b, const std::vector<bool>& object) {
  double squares = 0, signal = 0;
  for (std::size_t p = 0; p < object.size(); ++p) {
    if (!object[p]) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a.rgb[3 * p + c]) - b.rgb[3 * p + c];
      squares += d * d;
      signal += static_cast<double>(b.rgb[3 * p + c]) * b.rgb[3 * p + c];
    }
  }
  return std::sqrt(squares / signal);
}

/// Mean of channel c over the pixels fully covered by the object.
inline double covered_mean(const Image& image, const std::vector<float>& coverage, int c) {
  double sum = 0;
  int count = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f) {
      sum += image.rgb[3 * p + static_cast<std::size_t>(c)];
      ++count;
    }
  return count ? sum / count : 0.0;
}

/// A cube of side 2 about the origin with flat (per-face) normals.
inline TriangleMesh flat_cube() {
  TriangleMesh cube;
  const int faces[6][4][3] = {{{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}},     {{1, -1, -1}, {-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}},
                              {{1, -1, 1}, {1, -1, -1}, {1, 1, -1}, {1, 1, 1}},      {{-1, -1, -1}, {-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}},
                              {{-1, 1, 1}, {1, 1, 1}, {1, 1, -1}, {-1, 1, -1}},      {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}}};
  for (const auto& f : faces) {
    const auto base = static_cast<std::uint32_t>(cube.positions.size());
    Eigen::Vector3f q[4];
    for (int k = 0; k < 4; ++k) q[k] = Eigen::Vector3f(f[k][0], f[k][1], f[k][2]);
    const Eigen::Vector3f n = (q[1] - q[0]).cross(q[2] - q[0]).normalized();
    for (const auto& p : q) {
      cube.positions.push_back(p);
      cube.normals.push_back(n);
    }
    cube.triangles.push_back({base, base + 1, base + 2});
    cube.triangles.push_back({base, base + 2, base + 3});
  }
  return cube;
}

}  // namespace matlas::test
