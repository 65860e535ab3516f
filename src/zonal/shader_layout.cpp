#include "zonal/shader_layout.h"

#include <cmath>
#include <algorithm>
#include <cstddef>

#include "core/error.h"
#include "core/parallel.h"
#include "zonal/sh.h"

namespace matlas::zonal {

std::vector<float> pack_coefficients(const CoefficientSet& set) {
  const std::size_t block = static_cast<std::size_t>(set.settings.theta_o_count) *
                            triangle_size(set.settings.bands) * 3;
  std::vector<float> out((set.materials.size() + 1) * block, 0.0f);
  auto put = [&](const ZonalCoefficients& c, std::size_t slot) {
    if (c.values.size() != block) throw Error("coefficient set: a material's layout differs from the set's settings");
    for (std::size_t v = 0; v < block; ++v) out[slot * block + v] = static_cast<float>(c.values[v]);
  };
  if (set.mean) put(*set.mean, 0);
  for (std::size_t i = 0; i < set.materials.size(); ++i) put(set.materials[i], i + 1);
  return out;
}

EnvironmentAtlas pack_environment(const PrefilteredEnvironment& env) {
  EnvironmentAtlas atlas;
  atlas.bands = env.bands();
  atlas.height = env.map_height(atlas.bands);
  atlas.width = env.map_width(atlas.bands);
  const auto W = static_cast<std::size_t>(atlas.width), H = static_cast<std::size_t>(atlas.height);
  atlas.values.resize(static_cast<std::size_t>(atlas.bands + 1) * H * W * 3);
  parallel_for_each(0, static_cast<std::size_t>(atlas.bands + 1) * H, [&](std::size_t layer_row) {
    const int l = static_cast<int>(layer_row / H);
    const std::size_t y = layer_row % H;
    float* row = &atlas.values[layer_row * W * 3];
    if (l == atlas.bands) {
      const std::vector<float>& own = env.map(l);
      std::copy(own.begin() + static_cast<std::ptrdiff_t>(y * W * 3),
                own.begin() + static_cast<std::ptrdiff_t>((y + 1) * W * 3), row);
      return;
    }
    const double theta = kPi * static_cast<double>(y) / static_cast<double>(H - 1);
    for (std::size_t x = 0; x < W; ++x) {
      const double phi = 2.0 * kPi * static_cast<double>(x) / static_cast<double>(W);
      const Rgb e = env.lookup(l, Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
      for (int c = 0; c < 3; ++c) row[x * 3 + static_cast<std::size_t>(c)] = static_cast<float>(e[c]);
    }
  });
  return atlas;
}

}  // namespace matlas::zonal
