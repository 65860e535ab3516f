// Image bases without a model: composition is the explicit weighted sum (across storage tiles and
// SIMD remainders, in float32, float16 and the low-rank form); other files are refused. The bases
// of a model are tested in tests/atlas/test_model_basis.cpp.
#include <gtest/gtest.h>

#include <random>

#include "core/atomic_file.h"
#include "core/error.h"
#include "render/image_basis.h"
#include "support/temp_dir.h"

namespace matlas::render {
namespace {

TEST(ImageBasisCompose, EqualsTheExplicitWeightedSumAcrossTilesAndRemainders) {
  // 45 x 41 pixels, half of them active: several storage tiles, a packed length that is not a
  // multiple of the SIMD width, and n = 7 (not a multiple of the four-row blocking).
  const int w = 45, h = 41, n = 7;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  Image mean(w, h);
  std::vector<Image> images(n, Image(w, h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const bool active = (x + 2 * y) % 4 < 2;
        mean.pixel(x, y)[c] = 0.25f;
        for (Image& im : images) im.pixel(x, y)[c] = active ? u(rng) : 0.25f;
      }
  ImageBasis basis(mean, images);
  EXPECT_NEAR(basis.active_fraction(), 0.5, 0.01);
  Eigen::VectorXd weights(n);
  weights << 0.3, -0.2, 0.05, 0.6, 0.1, -0.4, 0.25;
  auto expected = [&](std::size_t k) {
    double v = (1.0 - weights.sum()) * mean.rgb[k];
    for (int i = 0; i < n; ++i) v += weights[i] * images[static_cast<std::size_t>(i)].rgb[k];
    return v;
  };
  const Image composed = basis.compose(weights);
  for (std::size_t k = 0; k < composed.rgb.size(); ++k) ASSERT_NEAR(composed.rgb[k], expected(k), 1e-5) << k;
  for (int i = 0; i < n; ++i) EXPECT_EQ(basis.material_image(i).rgb, images[static_cast<std::size_t>(i)].rgb);
  basis.convert_to_half();
  const Image half = basis.compose(weights);
  for (std::size_t k = 0; k < half.rgb.size(); ++k) ASSERT_NEAR(half.rgb[k], expected(k), 4e-3) << k;
  basis.compress(0.0);
  const Image low = basis.compose_low_rank(weights);
  for (std::size_t k = 0; k < low.rgb.size(); ++k) ASSERT_NEAR(low.rgb[k], half.rgb[k], 1e-4) << k;
}

TEST(ImageBasisFile, OpenRejectsOtherFiles) {
  test::TempDir dir("matlas-basis");
  write_file_atomic(dir / "junk.safetensors", std::string("not a basis at all"));
  EXPECT_THROW(ImageBasis::open(dir / "junk.safetensors"), Error);
  EXPECT_THROW(ImageBasis::open(dir / "missing.safetensors"), Error);
}

}  // namespace
}  // namespace matlas::render
