// Image bases of a model: the composed image of any weights equals the direct render of the
// manifold's BRDF at those weights; files round-trip with the model's fingerprint; float16 and
// low-rank forms have small measured errors.
#include <gtest/gtest.h>

#include <cmath>

#include "atlas/model_basis.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "brdf/catalog.h"
#include "core/check.h"
#include "core/error.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "support/temp_dir.h"

namespace matlas::atlas {

using render::BasisPrecision;
using render::Environment;
using render::ImageBasis;
using render::LowRankReport;
using render::RenderSettings;
using render::Scene;
using render::SceneDescription;
namespace {

/// A small model built once for the suite: 6 synthetic materials on a coarse grid.
class ImageBasisTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-basis");
    const MerlDims dims{16, 16, 32};
    write_database(dir_->path() / "db", random_catalog(6, 11), null_progress(), dims);
    const MaterialSet set = MaterialSet::open({dir_->path() / "db"});
    BuildOptions options;
    options.dim = 2;
    build_model(set, options, dir_->path() / "m.matlas");
    model_ = new Model(Model::open(dir_->path() / "m.matlas"));
  }
  static void TearDownTestSuite() {
    delete model_;
    delete dir_;
  }
  static Scene scene() {
    SceneDescription d;
    d.lights.push_back({Vec3(-0.4, 0.8, 0.5).normalized(), Rgb::Constant(1.0)});
    return Scene(d, std::nullopt, Environment(test::synthetic_environment()));
  }
  static RenderSettings settings() {
    RenderSettings s;
    s.width = 24;
    s.height = 20;
    s.spp = 6;
    s.seed = 5;
    return s;
  }
  static double max_relative(const Image& a, const Image& b) {
    double diff = 0, scale = 0;
    for (std::size_t k = 0; k < a.rgb.size(); ++k) {
      diff = std::max(diff, static_cast<double>(std::abs(a.rgb[k] - b.rgb[k])));
      scale = std::max(scale, static_cast<double>(std::abs(b.rgb[k])));
    }
    return diff / scale;
  }
  static test::TempDir* dir_;
  static Model* model_;
};
test::TempDir* ImageBasisTest::dir_ = nullptr;
Model* ImageBasisTest::model_ = nullptr;

TEST_F(ImageBasisTest, ComposedImageEqualsTheDirectRenderOfTheManifoldPoint) {
  const Scene s = scene();
  const ImageBasis basis = render_basis(*model_, s, settings());
  // The basis is rendered through the mixture fitted to the model (glossy materials: fitted
  // lobes, not the default ones), and direct renders of map points use the same one.
  const RenderSettings fitted = model_render_settings(*model_, settings());
  EXPECT_NE(fitted.mixture.lobes, RenderSettings().mixture.lobes);
  EXPECT_NE(basis.metadata().at("sampling_mixture").find("lobes"), std::string::npos);
  EXPECT_EQ(basis.count(), 6);
  EXPECT_EQ(basis.width(), 24);
  EXPECT_EQ(basis.height(), 20);
  EXPECT_GT(basis.active_fraction(), 0.2);
  EXPECT_LT(basis.active_fraction(), 1.0);
  // A point between materials and one outside the data (extrapolation, negative weights).
  const Eigen::MatrixXd& X = model_->latent();
  for (const Eigen::VectorXd& x : {Eigen::VectorXd(0.5 * (X.row(0) + X.row(3)).transpose()),
                                  Eigen::VectorXd(1.3 * X.row(2).transpose() - 0.2 * X.row(4).transpose())}) {
    const Eigen::VectorXd w = model_->weights(x);
    const Image direct = render::render(s, ModelMaterial(*model_, w), fitted);
    EXPECT_LT(max_relative(basis.compose(w), direct), 2e-6);
  }
  // Material images are the renders of the database materials.
  const Image direct2 = render::render(s, ModelMaterial(*model_, model_->material_weights(2)), fitted);
  EXPECT_LT(max_relative(basis.material_image(2), direct2), 1e-6);
  EXPECT_LT(max_relative(basis.compose(model_->material_weights(2)), direct2), 1e-6);
  EXPECT_THROW(basis.compose(Eigen::VectorXd::Zero(5)), InternalError);  // a bug of the caller, not bad input
}

TEST_F(ImageBasisTest, TheTableOfAModelPointRendersLikeItsLookups) {
  // ModelTableMaterial (the table built once) and ModelMaterial (a dot product per lookup) are
  // the same material: equal values at every direction, equal renders, and the composition of
  // the basis, at a point between materials and one outside the data.
  const Scene s = scene();
  const ImageBasis basis = render_basis(*model_, s, settings());
  const RenderSettings fitted = model_render_settings(*model_, settings());
  const Eigen::MatrixXd& X = model_->latent();
  for (const Eigen::VectorXd& x : {Eigen::VectorXd(0.5 * (X.row(1) + X.row(4)).transpose()),
                                  Eigen::VectorXd(1.4 * X.row(0).transpose() - 0.3 * X.row(5).transpose())}) {
    const Eigen::VectorXd w = model_->weights(x);
    const ModelMaterial lookups(*model_, w);
    const ModelTableMaterial table(*model_, w);
    std::uint64_t z = 99;
    const auto next = [&] {
      z = z * 6364136223846793005ull + 1442695040888963407ull;
      return static_cast<double>(z >> 11) * 0x1.0p-53;
    };
    for (int k = 0; k < 2000; ++k) {
      const auto direction = [&] {
        const double ct = next(), phi = 2 * kPi * next(), st = std::sqrt(1 - ct * ct);
        return Vec3(st * std::cos(phi), st * std::sin(phi), ct);
      };
      const Vec3 wi = direction(), wo = direction();
      const Rgb a = lookups.eval(wi, wo), b = table.eval(wi, wo);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(b[c], a[c], 1e-12 * (1 + std::abs(a[c]))) << "direction " << k;
    }
    const Image from_table = render::render(s, table, fitted);
    EXPECT_LT(max_relative(from_table, render::render(s, lookups, fitted)), 1e-6);
    EXPECT_LT(max_relative(basis.compose(w), from_table), 2e-6);
  }
}

TEST_F(ImageBasisTest, FilesRoundTripInFloat32AndFloat16) {
  ImageBasis basis = render_basis(*model_, scene(), settings());
  basis.metadata()["note"] = "test";
  basis.save(dir_->path() / "b32.safetensors");
  const Eigen::VectorXd w = model_->weights(model_->latent().colwise().mean().transpose());
  const Image reference = basis.compose(w);
  const ImageBasis b32 = ImageBasis::open(dir_->path() / "b32.safetensors");
  EXPECT_EQ(b32.names(), model_->names());
  EXPECT_EQ(b32.metadata().at("note"), "test");
  EXPECT_EQ(b32.metadata().at("spp"), "6");
  EXPECT_EQ(b32.metadata().at("model_fingerprint"), model_fingerprint(*model_));
  EXPECT_EQ(b32.compose(w).rgb, reference.rgb);

  basis.save(dir_->path() / "b16.safetensors", BasisPrecision::f16);
  const ImageBasis b16 = ImageBasis::open(dir_->path() / "b16.safetensors");
  EXPECT_EQ(b16.precision(), BasisPrecision::f16);
  const double err16 = max_relative(b16.compose(w), reference);
  EXPECT_LT(err16, 2e-3);
  EXPECT_GT(err16, 0.0);
  ImageBasis converted = basis;
  const double rel = converted.convert_to_half();
  EXPECT_GT(rel, 0.0);
  EXPECT_LT(rel, 1e-3);
  EXPECT_LT(max_relative(converted.compose(w), b16.compose(w)), 2e-3);
}

TEST_F(ImageBasisTest, LowRankFormIsExactAtFullRankAndReportsItsTruncationError) {
  ImageBasis basis = render_basis(*model_, scene(), settings());
  const Eigen::VectorXd w = model_->weights(model_->latent().row(1).transpose() * 0.9);
  const Image exact = basis.compose(w);
  const LowRankReport full = basis.compress(0.0);
  EXPECT_EQ(full.rank, 6);
  EXPECT_LT(max_relative(basis.compose_low_rank(w), exact), 1e-5);
  const LowRankReport two = basis.compress(0.0, 2);
  EXPECT_EQ(two.rank, 2);
  EXPECT_GT(two.relative_error, 0.0);
  // The error of each material image is bounded by the measured maximum.
  double worst = 0;
  for (int i = 0; i < basis.count(); ++i) {
    const Image approx = basis.compose_low_rank(model_->material_weights(i));
    const Image image = basis.material_image(i);
    for (std::size_t k = 0; k < image.rgb.size(); ++k)
      worst = std::max(worst, static_cast<double>(std::abs(approx.rgb[k] - image.rgb[k])));
  }
  EXPECT_LE(worst, two.max_abs_error * 1.001 + 1e-6);
  EXPECT_GT(worst, 0.5 * two.max_abs_error);
  basis.save(dir_->path() / "lr.safetensors");
  const ImageBasis reopened = ImageBasis::open(dir_->path() / "lr.safetensors");
  EXPECT_EQ(reopened.low_rank(), 2);
  EXPECT_LT(max_relative(reopened.compose_low_rank(w), basis.compose_low_rank(w)), 1e-6);
}

TEST_F(ImageBasisTest, OpenRejectsAModel) {
  EXPECT_THROW(ImageBasis::open(dir_->path() / "m.matlas"), Error);  // a model is not a basis
}

}  // namespace
}  // namespace matlas::atlas
