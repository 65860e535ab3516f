// The viewer's texture layouts: every band of a prefiltered environment on one octahedral grid
// (checked against the analytic filtered maps of a linear environment; its border continues the
// map across the edges), and the coefficient payload's order.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "render/environment.h"
#include "zonal/shader_layout.h"

namespace matlas::zonal {
namespace {

TEST(ShaderLayout, EnvironmentAtlasHoldsEveryBandOnOneOctahedralGrid) {
  // Radiance c0 + c . w: E_0 = sqrt(4 pi) c0, E_1(d) = sqrt(3/4pi) (4pi/3) c . d, E_l = 0 beyond.
  const double c0 = 1.5;
  const Vec3 c(0.3, 0.7, -0.2);
  Image map(128, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) {
      const double theta = kPi * (y + 0.5) / 64, phi = 2 * kPi * ((x + 0.5) / 128 - 0.5);
      const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      float* p = map.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<float>(c0 + c.dot(d));
    }
  PrefilterSettings s;
  s.bands = 3;
  const PrefilteredEnvironment env(render::Environment(map), s);
  const int N = 40, S = N + 2;
  const EnvironmentAtlas atlas = pack_environment(env, N);
  ASSERT_EQ(atlas.bands, 3);
  ASSERT_EQ(atlas.height, S);
  ASSERT_EQ(atlas.width, S);
  ASSERT_EQ(atlas.values.size(), 4u * static_cast<std::size_t>(S * S) * 3);
  auto at = [&](int l, int i, int j, int ch) {
    return atlas.values[((static_cast<std::size_t>(l) * S + j) * S + i) * 3 + ch];
  };
  // Interior texels: the direction of the octahedral point, decoded here independently (upper
  // half: (p_x, 1 - |p_x| - |p_z|, p_z); lower half: the triangles folded over the diagonals).
  for (int j = 1; j <= N; j += 3)
    for (int i = 1; i <= N; i += 5) {
      const double px = 2.0 * (i - 0.5) / N - 1, pz = 2.0 * (j - 0.5) / N - 1;
      const double y = 1 - std::abs(px) - std::abs(pz);
      Vec3 d = y >= 0 ? Vec3(px, y, pz)
                      : Vec3(std::copysign(1 - std::abs(pz), px), y, std::copysign(1 - std::abs(px), pz));
      d.normalize();
      EXPECT_NEAR(at(0, i, j, 0), std::sqrt(4 * kPi) * c0, 3e-3);
      EXPECT_NEAR(at(1, i, j, 1), std::sqrt(3 / (4 * kPi)) * (4 * kPi / 3) * c.dot(d), 2e-2) << i << " " << j;
      EXPECT_NEAR(at(2, i, j, 2), 0.0, 5e-3);
      EXPECT_NEAR(at(3, i, j, 0), 0.0, 5e-3);
    }
  // The border continues the map: column 0 is column 1 mirrored top to bottom (and likewise the
  // last column, the first and the last row), so bilinear reads across an edge are continuous.
  for (int k = 0; k < S; ++k)
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_EQ(at(1, 0, k, ch), at(1, 1, S - 1 - k, ch));
      EXPECT_EQ(at(1, S - 1, k, ch), at(1, S - 2, S - 1 - k, ch));
      EXPECT_EQ(at(1, k, 0, ch), at(1, S - 1 - k, 1, ch));
      EXPECT_EQ(at(1, k, S - 1, ch), at(1, S - 1 - k, S - 2, ch));
    }
  EXPECT_EQ(octahedral_side(16), 204);
}

TEST(ShaderLayout, CoefficientsAreTheMeanThenEachMaterial) {
  CoefficientSet set;
  set.settings.bands = 1;
  set.settings.theta_o_count = 2;
  const std::size_t block = 2 * 3 * 3;
  for (int i = 0; i < 2; ++i) {
    ZonalCoefficients c{1, 2, std::vector<double>(block)};
    for (std::size_t v = 0; v < block; ++v) c.values[v] = 100.0 * (i + 1) + static_cast<double>(v);
    set.materials.push_back(c);
  }
  std::vector<float> packed = pack_coefficients(set);
  ASSERT_EQ(packed.size(), 3 * block);
  EXPECT_EQ(packed[0], 0.0f);  // no mean: zeros
  EXPECT_EQ(packed[block + 5], 105.0f);
  EXPECT_EQ(packed[2 * block + 17], 217.0f);
  set.mean = ZonalCoefficients{1, 2, std::vector<double>(block, -1.0)};
  packed = pack_coefficients(set);
  EXPECT_EQ(packed[3], -1.0f);
  set.materials[1].values.pop_back();
  EXPECT_THROW(pack_coefficients(set), Error);
}

}  // namespace
}  // namespace matlas::zonal
