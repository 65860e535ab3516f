// Latent planes, grids, maps and galleries on a small synthetic model.
#include <gtest/gtest.h>

#include <set>

#include "brdf/catalog.h"
#include "core/error.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "render/gallery.h"
#include "render/image_basis.h"
#include "render/latent_map.h"
#include "render/render.h"
#include "render_test_util.h"
#include "support/temp_dir.h"

namespace matlas::render {
namespace {

class LatentMapTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-map");
    write_database(dir_->path() / "db", random_catalog(7, 21), null_progress(), MerlDims{12, 12, 24});
    BuildOptions options;
    options.dim = 3;
    build_model(MaterialSet::open({dir_->path() / "db"}), options, dir_->path() / "m.matlas");
    model_ = new Model(Model::open(dir_->path() / "m.matlas"));
  }
  static void TearDownTestSuite() {
    delete model_;
    delete dir_;
  }
  static test::TempDir* dir_;
  static Model* model_;
};
test::TempDir* LatentMapTest::dir_ = nullptr;
Model* LatentMapTest::model_ = nullptr;

TEST_F(LatentMapTest, PlanesCoverTheDataAndProjectConsistently) {
  const Eigen::VectorXd mean = model_->latent().colwise().mean().transpose();
  for (const LatentPlane& p : {LatentPlane::from_dims(*model_, 0, 2, mean), LatentPlane::pca(*model_, mean)}) {
    EXPECT_NEAR(p.axis_u.norm(), 1.0, 1e-12);
    EXPECT_NEAR(p.axis_u.dot(p.axis_v), 0.0, 1e-12);
    for (int i = 0; i < model_->count(); ++i) {
      const Eigen::Vector2d uv = p.project(model_->latent().row(i).transpose());
      EXPECT_GT(uv.x(), p.u_min);
      EXPECT_LT(uv.x(), p.u_max);
      EXPECT_GT(uv.y(), p.v_min);
      EXPECT_LT(uv.y(), p.v_max);
    }
    const Eigen::Vector2d back = p.project(p.point(0.3, -0.2));
    EXPECT_NEAR(back.x(), 0.3, 1e-12);
    EXPECT_NEAR(back.y(), -0.2, 1e-12);
  }
  // Axis-aligned plane: the other coordinate is the fixed point's.
  const LatentPlane p = LatentPlane::from_dims(*model_, 0, 2, mean);
  EXPECT_DOUBLE_EQ(p.point(1.0, 2.0)[1], mean[1]);
  EXPECT_THROW(LatentPlane::from_dims(*model_, 0, 0, mean), Error);
  EXPECT_THROW(LatentPlane::from_dims(*model_, 0, 1, Eigen::VectorXd::Zero(2)), Error);
}

TEST_F(LatentMapTest, GridWeightsAreThePosteriorWeights) {
  const LatentGrid g = latent_grid(*model_, LatentPlane::automatic(*model_), 5, 4);
  ASSERT_EQ(g.points.rows(), 20);
  ASSERT_EQ(g.weights.cols(), 20);
  for (int k : {0, 7, 19}) EXPECT_LT((g.weights.col(k) - model_->weights(g.points.row(k).transpose())).norm(), 1e-9);
  // Row 0 is the top of the picture (largest v).
  EXPECT_GT(g.points(0, 1), g.points(15, 1));
}

TEST_F(LatentMapTest, AlbedoAndVarianceLayersColourTheGrid) {
  const LatentPlane plane = LatentPlane::automatic(*model_);
  MapOptions o;
  o.size = 64;
  o.cells = 8;
  o.labels = false;
  const Image albedo = render_latent_map(*model_, plane, o);
  const LatentGrid g = latent_grid(*model_, plane, 8, 8);
  const Rgb a = model_->albedo_curve(g.weights.col(0)).front();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(albedo.pixel(1, 1)[c], std::clamp(a[c], 0.0, 1.0), 1e-6);
  o.layer = MapLayer::variance;
  const Image variance = render_latent_map(*model_, plane, o);
  const Eigen::Array3d v = colour_map(model_->variance(g.points.row(0).transpose()));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(variance.pixel(1, 1)[c], v[c], 1e-6);
  o.layer = MapLayer::image;
  EXPECT_THROW(render_latent_map(*model_, plane, o), Error);  // no basis
}

TEST_F(LatentMapTest, GalleryPicksAreDeterministicShuffledAndKeyed) {
  GalleryOptions o;
  o.random = 5;
  o.real = 3;
  o.seed = 4;
  const auto a = pick_gallery(*model_, o), b = pick_gallery(*model_, o);
  ASSERT_EQ(a.size(), 8u);
  int real = 0;
  std::set<std::string> names(model_->names().begin(), model_->names().end());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].x, b[k].x);
    if (a[k].real) {
      ++real;
      EXPECT_TRUE(names.count(a[k].name));
    } else {
      EXPECT_NEAR(a[k].variance, model_->variance(a[k].x), 1e-12);
    }
  }
  EXPECT_EQ(real, 3);
  o.seed = 5;
  const auto c = pick_gallery(*model_, o);
  bool differs = false;
  for (std::size_t k = 0; k < a.size(); ++k) differs |= a[k].x != c[k].x;
  EXPECT_TRUE(differs);

  SceneDescription d;
  const Scene scene(d, std::nullopt, Environment(test::synthetic_environment()));
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = 2;
  const ImageBasis basis = render_basis(*model_, scene, s);
  const Image grid = render_gallery(*model_, a, nullptr, nullptr, &basis);
  EXPECT_GT(grid.width, 3 * 16);
  EXPECT_GT(grid.height, 2 * 16);
  const nlohmann::json key = gallery_key(a);
  ASSERT_EQ(key.size(), 8u);
  EXPECT_EQ(key[0]["cell"], 1);
  o.real = 100;
  EXPECT_THROW(pick_gallery(*model_, o), Error);
  // The image layer of the map composes thumbnails from the basis.
  MapOptions m;
  m.layer = MapLayer::image;
  m.size = 32;
  m.thumbnails = 2;
  m.basis = &basis;
  m.labels = false;
  EXPECT_EQ(render_latent_map(*model_, LatentPlane::automatic(*model_), m).width, 32);
}

}  // namespace
}  // namespace matlas::render
