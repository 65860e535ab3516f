// Renderer against closed forms: Lambertian spheres and cubes under a constant environment and
// under a directional light, analytic GGX vs its table, linearity and determinism.
#include <gtest/gtest.h>

#include <cmath>

#include "brdf/analytic.h"
#include "core/error.h"
#include "brdf/tabulate.h"
#include "render/material.h"
#include "render/render.h"
#include "render/scene.h"
#include "support/ortho_sphere.h"
#include "render_test_util.h"

namespace matlas::render {
namespace {

RenderSettings small(int size, int spp) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.seed = 7;
  return s;
}

RenderSettings cosine_only(RenderSettings s) {
  s.mixture = {0.0, 1.0, {}};
  s.sampler = Sampler::stratified;  // the default light-and-lobe sampler always adds an environment sample
  return s;
}

TEST(Render, LambertianSphereUnderConstantEnvironmentEqualsAlbedoExactly) {
  SceneDescription d;
  d.constant_radiance = Rgb(1.0, 0.5, 2.0);
  const Scene scene(d);
  const Lambertian lambert{Rgb(0.8, 0.4, 0.2)};
  const FunctionMaterial material([&](const Vec3& wi, const Vec3& wo) { return lambert(wi, wo); });
  // With cosine sampling alone the estimator is albedo * L for every sample: exact per pixel.
  const RenderSettings settings = cosine_only(small(24, 4));
  const Image image = render(scene, material, settings);
  const std::vector<float> coverage = object_coverage(scene, settings);
  int covered = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p) {
    if (coverage[p] != 1.0f) continue;
    ++covered;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(image.rgb[3 * p + c], lambert.albedo[c] * d.constant_radiance[c], 1e-5) << "pixel " << p;
  }
  EXPECT_GT(covered, 200);
}

TEST(Render, LambertianSphereWithTheDefaultMixtureIsUnbiased) {
  SceneDescription d;
  const Scene scene(d);
  const Lambertian lambert{Rgb(0.8, 0.4, 0.2)};
  const FunctionMaterial material([&](const Vec3& wi, const Vec3& wo) { return lambert(wi, wo); });
  const RenderSettings settings = small(16, 64);
  const Image image = render(scene, material, settings);
  const std::vector<float> coverage = object_coverage(scene, settings);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(test::covered_mean(image, coverage, c), lambert.albedo[c], 0.01 * lambert.albedo[c]);
  // Per pixel the estimate is noisy (64 samples) but centred on the albedo.
  double sq = 0;
  int count = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f) {
      sq += std::pow(image.rgb[3 * p] / 0.8 - 1.0, 2);
      ++count;
    }
  EXPECT_LT(std::sqrt(sq / count), 0.2);
}

TEST(Render, LambertianCubeMeshUnderConstantEnvironmentEqualsAlbedo) {
  // A cube with flat (per-face) normals: every visible point sees the whole upper hemisphere.
  const TriangleMesh cube = test::flat_cube();
  SceneDescription d;
  d.object = "cube";
  d.camera.position = Vec3(2.5, 2.0, 3.5);
  const Scene scene(d, cube, Environment::constant(Rgb::Constant(1.0)));
  const FunctionMaterial material([](const Vec3&, const Vec3&) -> Rgb { return Rgb(0.5, 0.25, 0.125) / kPi; });
  const RenderSettings settings = cosine_only(small(24, 4));
  const Image image = render(scene, material, settings);
  const std::vector<float> coverage = object_coverage(scene, settings);
  int covered = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f) {
      ++covered;
      EXPECT_NEAR(image.rgb[3 * p], 0.5, 1e-4);
      EXPECT_NEAR(image.rgb[3 * p + 2], 0.125, 1e-4);
    }
  EXPECT_GT(covered, 100);
}

TEST(Render, LambertianSphereUnderDirectionalLightIsAlbedoOverPiTimesCosine) {
  SceneDescription d;
  d.constant_radiance = Rgb::Zero();
  d.camera.orthographic = true;
  d.camera.position = Vec3(0, 0, 5);
  d.camera.ortho_height = 2.2;
  const Vec3 light = Vec3(0.3, 0.5, 0.8).normalized();
  d.lights.push_back({light, Rgb(2.0, 1.0, 0.5)});
  d.show_environment = false;
  const Scene scene(d);
  const Rgb albedo(0.9, 0.6, 0.3);
  const FunctionMaterial material([&](const Vec3& wi, const Vec3& wo) { return Lambertian{albedo}(wi, wo); });
  const RenderSettings settings = small(48, 16);
  const Image image = render(scene, material, settings);
  int checked = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const auto normal = test::ortho_sphere_normal(x, y, settings.width, settings.height);
      if (!normal) continue;  // away from the silhouette
      const Vec3 n = *normal;
      const double cos_theta = n.dot(light);
      if (std::abs(cos_theta) < 0.1) continue;  // and from the terminator
      ++checked;
      for (int c = 0; c < 3; ++c) {
        const double expected = albedo[c] / kPi * d.lights[0].irradiance[c] * std::max(cos_theta, 0.0);
        EXPECT_NEAR(image.pixel(x, y)[c], expected, 0.01) << x << "," << y;
      }
    }
  EXPECT_GT(checked, 800);
}

TEST(Render, TabulatedGgxRendersLikeTheAnalyticBrdf) {
  const GgxConductor ggx{Rgb(0.95, 0.64, 0.54), 0.3};
  const BrdfTable table = tabulate(ggx);
  SceneDescription d;
  const Scene scene(d, std::nullopt, Environment(test::synthetic_environment()));
  const RenderSettings settings = small(32, 32);
  const Image analytic = render(scene, FunctionMaterial([&](const Vec3& wi, const Vec3& wo) { return ggx(wi, wo); }), settings);
  const Image tabulated = render(scene, TableMaterial(table), settings);
  const std::vector<float> coverage = object_coverage(scene, settings);
  for (int c = 0; c < 3; ++c) {
    const double a = test::covered_mean(analytic, coverage, c), t = test::covered_mean(tabulated, coverage, c);
    EXPECT_GT(a, 0.01);
    EXPECT_NEAR(t, a, 0.03 * a) << "channel " << c;
  }
  double diff2 = 0, norm2 = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f) {
      const double dlt = analytic.rgb[3 * p + 1] - tabulated.rgb[3 * p + 1];
      diff2 += dlt * dlt;
      norm2 += analytic.rgb[3 * p + 1] * analytic.rgb[3 * p + 1];
    }
  EXPECT_LT(std::sqrt(diff2 / norm2), 0.08);
}

TEST(Render, ATableCombinationIsTheWeightedSumOfItsTables) {
  // Two small tables (coarse grid) with missing bins in one: the combination's value at any pair
  // of directions is a*T1 + b*T2 with missing values read as 0, and its render is the same
  // weighted sum of the tables' renders (the estimator is linear in f with shared samples; the
  // coefficients sum to 1 so that the background, which no BRDF touches, is the same too).
  const MerlDims dims{8, 8, 16};
  const BrdfTable t1 = tabulate(Lambertian{Rgb(0.8, 0.4, 0.2)}, dims);
  BrdfTable t2 = tabulate(GgxConductor{Rgb(0.9, 0.6, 0.5), 0.4}, dims);
  for (std::size_t b = 0; b < t2.bins(); b += 7) t2.set_missing(1, b);
  const TableCombination mix({&t1, &t2}, {1.25, -0.25});
  for (const auto& [wi, wo] : {std::pair{Vec3(0, 0, 1), Vec3(0.3, 0.1, 0.9).normalized()},
                               std::pair{Vec3(0.6, -0.2, 0.5).normalized(), Vec3(-0.5, 0.2, 0.6).normalized()}}) {
    const Rgb expected = 1.25 * t1.lookup(wi, wo) - 0.25 * t2.lookup(wi, wo);
    const Rgb got = mix.eval(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-12 * (1 + std::abs(expected[c])));
  }
  const Scene scene(SceneDescription{}, std::nullopt, Environment(test::synthetic_environment()));
  const RenderSettings settings = small(16, 4);
  const Image a = render(scene, TableMaterial(t1), settings), b = render(scene, TableMaterial(t2), settings);
  const Image m = render(scene, mix, settings);
  for (std::size_t k = 0; k < m.rgb.size(); ++k)
    ASSERT_NEAR(m.rgb[k], 1.25 * a.rgb[k] - 0.25 * b.rgb[k], 1e-5 * (1 + std::abs(a.rgb[k]) + std::abs(b.rgb[k]))) << k;
  EXPECT_THROW(TableCombination({&t1}, {1.0, 2.0}), Error);
  EXPECT_THROW(TableCombination({}, {}), Error);
  const BrdfTable other(MerlDims{4, 4, 8});
  EXPECT_THROW(TableCombination({&t1, &other}, {1.0, 1.0}), Error);
}

/// A sphere on the ground under a light and a synthetic environment.
SceneDescription lit_sphere_on_ground() {
  SceneDescription d;
  d.ground = true;
  d.lights.push_back({Vec3(0.5, 1.0, 0.3).normalized(), Rgb::Constant(1.5)});
  return d;
}

/// A glossy conductor and a diffuse material, as materials.
const GgxConductor kConductor{Rgb(0.9, 0.8, 0.5), 0.1};
const Lambertian kDiffuse{Rgb(0.2, 0.5, 0.7)};
const FunctionMaterial kConductorMaterial([](const Vec3& wi, const Vec3& wo) { return kConductor(wi, wo); });
const FunctionMaterial kDiffuseMaterial([](const Vec3& wi, const Vec3& wo) { return kDiffuse(wi, wo); });

TEST(Render, IsLinearInTheBrdfAndDeterministic) {
  const Scene scene(lit_sphere_on_ground(), std::nullopt, Environment(test::synthetic_environment(), 40.0));
  const GgxConductor& a = kConductor;
  const Lambertian& b = kDiffuse;
  const FunctionMaterial& fa = kConductorMaterial;
  const FunctionMaterial& fb = kDiffuseMaterial;
  const FunctionMaterial mix([&](const Vec3& wi, const Vec3& wo) { return Rgb(0.3 * a(wi, wo) + 0.7 * b(wi, wo)); });
  const RenderSettings settings = small(20, 8);
  const Image ia = render(scene, fa, settings), ib = render(scene, fb, settings), im = render(scene, mix, settings);
  for (std::size_t k = 0; k < im.rgb.size(); ++k)
    EXPECT_NEAR(im.rgb[k], 0.3f * ia.rgb[k] + 0.7f * ib.rgb[k], 1e-5f * (1.0f + std::abs(im.rgb[k])));
  // Same seed: identical; the bank renders both with the very same samples.
  EXPECT_EQ(render(scene, fa, settings).rgb, ia.rgb);
  const std::vector<Image> bank = render_bank(scene, MaterialList({&fa, &fb}), settings);
  ASSERT_EQ(bank.size(), 2u);
  for (std::size_t k = 0; k < ia.rgb.size(); ++k) {
    EXPECT_NEAR(bank[0].rgb[k], ia.rgb[k], 1e-6f * (1.0f + ia.rgb[k]));
    EXPECT_NEAR(bank[1].rgb[k], ib.rgb[k], 1e-6f * (1.0f + ib.rgb[k]));
  }
  RenderSettings other = settings;
  other.seed = 8;
  EXPECT_NE(render(scene, fa, other).rgb, ia.rgb);
}

TEST(Render, ABanksRowSharesAreTheWholeRendersRows) {
  // Every third row from rows 0, 1 and 2 (a render split across three processes): each share's
  // row j is the whole render's row part + 3 j, bit for bit, and the shares cover the image. A
  // height that 3 does not divide gives the shares different row counts.
  const Scene scene(lit_sphere_on_ground(), std::nullopt, Environment(test::synthetic_environment(), 40.0));
  const MaterialList bank({&kConductorMaterial, &kDiffuseMaterial});
  RenderSettings settings = small(16, 4);
  settings.height = 11;
  const std::vector<Image> whole = render_bank(scene, bank, settings);
  int covered = 0;
  for (int part = 0; part < 3; ++part) {
    const RowShare share{part, 3};
    const std::vector<Image> mine = render_bank(scene, bank, settings, null_progress(), nullptr, share);
    ASSERT_EQ(mine.size(), 2u);
    EXPECT_EQ(mine[0].height, part < 2 ? 4 : 3);  // rows 0,3,6,9 / 1,4,7,10 / 2,5,8
    for (std::size_t k = 0; k < 2; ++k)
      for (int j = 0; j < mine[k].height; ++j)
        for (int x = 0; x < settings.width; ++x)
          for (int c = 0; c < 3; ++c)
            EXPECT_EQ(mine[k].pixel(x, j)[c], whole[k].pixel(x, share.row(j))[c]) << part << " " << j << " " << x;
    covered += mine[0].height;
  }
  EXPECT_EQ(covered, settings.height);
}

TEST(Render, RejectsBadSettings) {
  const Scene scene{SceneDescription{}};
  const FunctionMaterial black([](const Vec3&, const Vec3&) { return Rgb(Rgb::Zero()); });
  RenderSettings s = small(8, 0);
  EXPECT_THROW(render(scene, black, s), Error);
  s = small(0, 4);
  EXPECT_THROW(render(scene, black, s), Error);
}

}  // namespace
}  // namespace matlas::render
