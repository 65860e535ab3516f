// Gallery picks on a database with a crowded cluster (a dozen near-identical pinkish diffuse
// materials next to a few diverse ones, the situation of issue 11): the picks must cover the
// database's variety instead of the cluster.
#include <gtest/gtest.h>

#include <cmath>

#include "atlas/gallery.h"
#include "brdf/catalog.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "support/temp_dir.h"

namespace matlas::atlas {
namespace {

class GalleryTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-gallery");
    std::vector<SynthMaterial> catalog;
    for (int i = 0; i < 14; ++i) {
      const double j = 0.004 * (i % 5) - 0.008, k = 0.003 * (i % 3);
      catalog.push_back({"pink-" + std::to_string(i), Lambertian{Rgb(0.55 + j, 0.33 + k, 0.38 - j)}});
    }
    for (SynthMaterial& m : random_catalog(10, 5)) catalog.push_back(std::move(m));
    write_database(dir_->path() / "db", catalog, null_progress(), MerlDims{12, 12, 24});
    BuildOptions options;
    options.dim = 3;
    build_model(MaterialSet::open({dir_->path() / "db"}), options, dir_->path() / "m.matlas");
    model_ = new Model(Model::open(dir_->path() / "m.matlas"));
  }
  static void TearDownTestSuite() {
    delete model_;
    delete dir_;
  }
  /// Whether a pick looks like the cluster: albedo within 10 % of the pink and no gloss.
  static bool in_cluster(const GalleryEntry& e) {
    const Eigen::Vector3d pink(0.55, 0.33, 0.38);
    return ((e.albedo - pink).array().abs() / pink.array()).maxCoeff() < 0.1 && e.gloss < 0.5;
  }
  static test::TempDir* dir_;
  static Model* model_;
};
test::TempDir* GalleryTest::dir_ = nullptr;
Model* GalleryTest::model_ = nullptr;

TEST_F(GalleryTest, FeaturesSeparateDiffuseFromGlossyAndColours) {
  const AppearanceFeatures f(*model_);
  const Eigen::MatrixXd raw = f.raw(Eigen::MatrixXd::Identity(model_->count(), model_->count()));
  // Lambertian: pi f / albedo = 1 at every bin, so gloss ~ 0; the pink's chromaticity is red.
  for (int k = 0; k < 14; ++k) {
    const int i = model_->index_of("pink-" + std::to_string(k));
    EXPECT_NEAR(raw(i, 3), 0.0, 0.1) << model_->names()[static_cast<std::size_t>(i)];
    EXPECT_GT(raw(i, 1), 0.3);
  }
  // Scaled features are the raw ones over the spread; the cluster's members are near each other.
  EXPECT_NEAR(f.materials()(3, 0), raw(3, 0) / f.scale()[0], 1e-12);
  const int a = model_->index_of("pink-0"), b = model_->index_of("pink-1");
  EXPECT_LT((f.materials().row(a) - f.materials().row(b)).norm(), 0.25);
}

TEST_F(GalleryTest, PicksCoverTheVarietyNotTheCrowdedCluster) {
  GalleryOptions o;
  o.random = 8;
  o.real = 3;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    o.seed = seed;
    GalleryStats stats;
    const std::vector<GalleryEntry> picks = pick_gallery(*model_, o, &stats);
    ASSERT_EQ(picks.size(), 11u);
    // Pairwise distinct in appearance (the features of the picks, recomputed independently).
    const AppearanceFeatures f(*model_);
    Eigen::MatrixXd W(model_->count(), static_cast<Eigen::Index>(picks.size()));
    for (std::size_t k = 0; k < picks.size(); ++k)
      W.col(static_cast<Eigen::Index>(k)) = picks[k].real ? model_->material_weights(model_->index_of(picks[k].name))
                                                          : model_->weights(picks[k].x);
    const Eigen::MatrixXd F = f(W);
    double closest = 1e300;
    for (Eigen::Index a = 0; a < F.rows(); ++a)
      for (Eigen::Index b = a + 1; b < F.rows(); ++b) closest = std::min(closest, (F.row(a) - F.row(b)).norm());
    EXPECT_GT(closest, 0.3) << "seed " << seed;
    EXPECT_NEAR(closest, stats.min_distance, 1e-9);
    // The cluster is 14 of 24 materials; the picks show it at most twice.
    int cluster = 0, generated = 0;
    for (const GalleryEntry& e : picks) {
      cluster += in_cluster(e);
      if (!e.real) {
        ++generated;
        EXPECT_LE(e.variance, o.max_variance + 1e-12);
        EXPECT_TRUE(e.plausible);
        EXPECT_GE(e.novelty, o.min_novelty);
        // The candidates' weights and variances come from one batch (K^-1 by dsymm): the same as
        // point by point to rounding.
        EXPECT_NEAR(e.variance, model_->variance(e.x), 1e-10);
      }
    }
    EXPECT_EQ(generated, 8);
    EXPECT_LE(cluster, 2) << "seed " << seed;
    EXPECT_TRUE(stats.relaxed.empty());
    EXPECT_GT(stats.candidates, 8);
  }
}

}  // namespace
}  // namespace matlas::atlas
