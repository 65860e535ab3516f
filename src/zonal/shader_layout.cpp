#include "zonal/shader_layout.h"

#include <cmath>
#include <algorithm>
#include <cstddef>

#include <string>

#include "core/error.h"
#include "core/parallel.h"
#include "zonal/sh.h"

namespace matlas::zonal {

std::vector<float> pack_coefficients(const CoefficientSet& set) {
  const std::size_t block = static_cast<std::size_t>(set.settings.theta_o_count) *
                            (triangle_size(set.settings.bands) + set.settings.lobes.size()) * 3;
  std::vector<float> out((set.materials.size() + 1) * block, 0.0f);
  auto put = [&](const ZonalCoefficients& c, std::size_t slot) {
    if (c.values.size() != block) throw Error("coefficient set: a material's layout differs from the set's settings");
    for (std::size_t v = 0; v < block; ++v) out[slot * block + v] = static_cast<float>(c.values[v]);
  };
  if (set.mean) put(*set.mean, 0);
  for (std::size_t i = 0; i < set.materials.size(); ++i) put(set.materials[i], i + 1);
  return out;
}

int octahedral_side(int bands) { return 12 * (bands + 1); }

Vec3 octahedral_direction(double px, double pz) {
  if (std::abs(px) > 1.0) {
    px = std::copysign(2.0, px) - px;
    pz = -pz;
  }
  if (std::abs(pz) > 1.0) {
    pz = std::copysign(2.0, pz) - pz;
    px = -px;
  }
  const double y = 1.0 - std::abs(px) - std::abs(pz);
  if (y < 0.0) {
    const double x = (1.0 - std::abs(pz)) * (px < 0.0 ? -1.0 : 1.0);
    pz = (1.0 - std::abs(px)) * (pz < 0.0 ? -1.0 : 1.0);
    px = x;
  }
  return Vec3(px, y, pz).normalized();
}

EnvironmentAtlas pack_environment(const PrefilteredEnvironment& env, int side) {
  EnvironmentAtlas atlas;
  atlas.bands = env.bands();
  const int N = side > 0 ? side : octahedral_side(atlas.bands);
  atlas.width = atlas.height = N + 2;
  const auto S = static_cast<std::size_t>(N + 2);
  atlas.values.resize(static_cast<std::size_t>(atlas.bands + 1) * S * S * 3);
  parallel_for_each(0, S, [&](std::size_t j) {
    const double pz = 2.0 * (static_cast<double>(j) - 0.5) / N - 1.0;
    for (std::size_t i = 0; i < S; ++i) {
      const Vec3 d = octahedral_direction(2.0 * (static_cast<double>(i) - 0.5) / N - 1.0, pz);
      for (int l = 0; l <= atlas.bands; ++l) {
        const Rgb e = env.lookup(l, d);
        float* texel = &atlas.values[((static_cast<std::size_t>(l) * S + j) * S + i) * 3];
        for (int c = 0; c < 3; ++c) texel[c] = static_cast<float>(e[c]);
      }
    }
  });
  return atlas;
}

EnvironmentAtlas pack_detail(const PrefilteredEnvironment& env, const render::Environment& raw, int side) {
  if (side < 4 || side > 4096) throw Error("detail atlas side must be between 4 and 4096, got " + std::to_string(side));
  EnvironmentAtlas atlas;
  const std::size_t M = env.lobes().size();
  atlas.bands = static_cast<int>(M);  // layers: M lobe maps and the background
  atlas.width = atlas.height = side + 2;
  const auto S = static_cast<std::size_t>(side + 2);
  atlas.values.resize((M + 1) * S * S * 3);
  parallel_for_each(0, S, [&](std::size_t j) {
    const double pz = 2.0 * (static_cast<double>(j) - 0.5) / side - 1.0;
    for (std::size_t i = 0; i < S; ++i) {
      const Vec3 d = octahedral_direction(2.0 * (static_cast<double>(i) - 0.5) / side - 1.0, pz);
      for (std::size_t layer = 0; layer <= M; ++layer) {
        const Rgb e = layer < M ? env.lobe_lookup(layer, d) : raw.eval_smooth(d);
        float* texel = &atlas.values[((layer * S + j) * S + i) * 3];
        for (int c = 0; c < 3; ++c) texel[c] = static_cast<float>(e[c]);
      }
    }
  });
  return atlas;
}

}  // namespace matlas::zonal
