// Image bases without a model: composition is the explicit weighted sum (across storage tiles and
// SIMD remainders, in float32, float16 and the low-rank form); other files are refused. The bases
// of a model are tested in tests/atlas/test_model_basis.cpp.
#include <gtest/gtest.h>

#include <limits>
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

TEST(ImageBasisCompose, ReadsOnlyTheImagesOfNonZeroWeights) {
  // Image 1 holds NaN: a composition whose weight for it is zero never reads it (convex weights
  // name a handful of materials), in float32 and float16; any other is the explicit sum.
  const int w = 20, h = 9, n = 6;
  Image mean(w, h);
  std::vector<Image> images(n, Image(w, h));
  for (std::size_t k = 0; k < mean.rgb.size(); ++k) {
    mean.rgb[k] = 0.5f;
    for (int i = 0; i < n; ++i) images[static_cast<std::size_t>(i)].rgb[k] = 0.1f * static_cast<float>(i + 1) + 1e-3f * static_cast<float>(k % 7);
  }
  for (float& v : images[1].rgb) v = std::numeric_limits<float>::quiet_NaN();
  ImageBasis basis(mean, images);
  Eigen::VectorXd weights(n);
  weights << 0.2, 0.0, 0.0, 0.5, 0.0, 0.3;
  for (const bool half : {false, true}) {
    if (half) basis.convert_to_half();
    const Image composed = basis.compose(weights);
    for (std::size_t k = 0; k < composed.rgb.size(); ++k) {
      double v = 0;
      for (int i : {0, 3, 5}) v += weights[i] * images[static_cast<std::size_t>(i)].rgb[k];
      ASSERT_NEAR(composed.rgb[k], v, half ? 2e-3 : 1e-6) << k;
    }
  }
}

TEST(ImageBasisCompose, APixelWhereOnlyTheMeanDiffersIsComposed) {
  // Every material has 0.5 at pixel 0 but the mean 0.25 (a GI basis's mean table can differ from
  // inputs that agree: I2 is not linear in the table); weights summing to 0.4 give 0.6 * 0.25 +
  // 0.4 * 0.5 there, not the mean.
  const int n = 3;
  Image mean(4, 1);
  std::vector<Image> images(n, Image(4, 1));
  for (std::size_t k = 0; k < mean.rgb.size(); ++k) {
    mean.rgb[k] = k < 3 ? 0.25f : 0.5f;
    for (int i = 0; i < n; ++i) images[static_cast<std::size_t>(i)].rgb[k] = k < 3 ? 0.5f : 0.1f * static_cast<float>(i);
  }
  const ImageBasis basis(mean, images);
  const Image composed = basis.compose(Eigen::Vector3d(0.1, 0.1, 0.2));
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(composed.rgb[c], 0.35, 1e-6) << c;
}

TEST(ImageBasisCompose, AnOffsetIsAddedToEveryCompositionAndSavedWithTheBasis) {
  // I(w) = offset + (1 - sum w) mean + sum w_i I_i, at active pixels and elsewhere, in memory
  // and after a save and open (float32 and float16 files).
  const int w = 10, h = 6, n = 3;
  Image mean(w, h), offset(w, h);
  std::vector<Image> images(n, Image(w, h));
  for (std::size_t k = 0; k < mean.rgb.size(); ++k) {
    mean.rgb[k] = 0.2f;
    offset.rgb[k] = 0.01f * static_cast<float>(k % 11);
    for (int i = 0; i < n; ++i)  // the first half of the pixels active
      images[static_cast<std::size_t>(i)].rgb[k] = k < mean.rgb.size() / 2 ? 0.1f * static_cast<float>(i + 1) : 0.2f;
  }
  ImageBasis basis(mean, images);
  basis.set_offset(offset);
  EXPECT_NEAR(basis.active_fraction(), 0.5, 1e-9);
  const Eigen::Vector3d weights(0.2, 0.3, 0.1);
  const test::TempDir dir;
  basis.save(dir.path() / "f32.safetensors");
  basis.save(dir.path() / "f16.safetensors", BasisPrecision::f16);
  const ImageBasis f32 = ImageBasis::open(dir.path() / "f32.safetensors"), f16 = ImageBasis::open(dir.path() / "f16.safetensors");
  EXPECT_EQ(f32.offset_image().rgb, offset.rgb);
  for (const ImageBasis* b : {static_cast<const ImageBasis*>(&basis), &f32, &f16}) {
    const Image composed = b->compose(weights);
    for (std::size_t k = 0; k < composed.rgb.size(); ++k) {
      double v = offset.rgb[k] + (1.0 - weights.sum()) * mean.rgb[k];
      for (int i = 0; i < n; ++i) v += weights[i] * images[static_cast<std::size_t>(i)].rgb[k];
      ASSERT_NEAR(composed.rgb[k], v, b == &f16 ? 1e-3 : 1e-6) << k;
    }
  }
  EXPECT_THROW(basis.set_offset(Image(w + 1, h)), Error);
}

TEST(ImageBasisCompose, ComposeFastIsExactForFewWeightsAndLowRankOtherwise) {
  // Rank 2 of 6 images: weights on at most 2 materials read no more images exactly than the 2
  // factors, so compose_fast composes them exactly (bit for bit); weights on 3 go through the
  // low-rank form (the same values as compose_low_rank, not the exact ones).
  const int w = 16, h = 8, n = 6;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image mean(w, h);
  std::vector<Image> images(n, Image(w, h));
  for (std::size_t k = 0; k < mean.rgb.size(); ++k) {
    mean.rgb[k] = 0.5f;
    for (Image& im : images) im.rgb[k] = u(rng);
  }
  ImageBasis basis(mean, images);
  basis.compress(0.0, 2);
  ASSERT_EQ(basis.low_rank(), 2);
  Eigen::VectorXd two = Eigen::VectorXd::Zero(n), three = Eigen::VectorXd::Zero(n);
  two << 0.0, 0.7, 0.0, 0.0, 0.3, 0.0;
  three << 0.2, 0.5, 0.0, 0.3, 0.0, 0.0;
  EXPECT_EQ(basis.compose_fast(two).rgb, basis.compose(two).rgb);
  EXPECT_NE(basis.compose_low_rank(two).rgb, basis.compose(two).rgb);
  EXPECT_EQ(basis.compose_fast(three).rgb, basis.compose_low_rank(three).rgb);
  EXPECT_NE(basis.compose_fast(three).rgb, basis.compose(three).rgb);
}

TEST(ImageBasisFile, OpenRejectsOtherFiles) {
  test::TempDir dir("matlas-basis");
  write_file_atomic(dir / "junk.safetensors", std::string("not a basis at all"));
  EXPECT_THROW(ImageBasis::open(dir / "junk.safetensors"), Error);
  EXPECT_THROW(ImageBasis::open(dir / "missing.safetensors"), Error);
}

}  // namespace
}  // namespace matlas::render
