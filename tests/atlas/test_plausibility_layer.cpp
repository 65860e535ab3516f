// The plausibility layer of a convex model whose inputs are all plausible: nothing to find, so it
// probes no cell and fades far from the data like the albedo layer (and costs what it costs);
// with the GP's weights, or an implausible input, it probes every cell and stays opaque.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "atlas/latent_plane.h"
#include "atlas/map_layers.h"
#include "brdf/catalog.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"
#include "support/temp_dir.h"

namespace matlas::atlas {
namespace {

/// Matte and rough coated materials with albedos well below 1 (also on a coarse table).
std::vector<SynthMaterial> gentle_catalog() {
  std::vector<SynthMaterial> out;
  const double shades[] = {0.1, 0.3, 0.5, 0.7};
  for (int k = 0; k < 4; ++k) {
    const Rgb c(shades[k], 0.6 * shades[(k + 1) % 4], 0.4 + 0.1 * k);
    out.push_back({"lambert-" + std::to_string(k), Lambertian{c}});
    RoughPlastic p;
    p.diffuse = 0.8 * c;
    p.alpha = 0.3 + 0.1 * k;
    p.specular = 0.5;
    out.push_back({"plastic-" + std::to_string(k), p});
  }
  return out;
}

Model* build(const std::filesystem::path& dir, const std::vector<SynthMaterial>& catalog) {
  write_database(dir / "db", catalog, null_progress(), MerlDims{12, 12, 24});
  BuildOptions options;
  options.dim = 2;
  build_model(MaterialSet::open({dir / "db"}), options, dir / "m.matlas");
  return new Model(Model::open(dir / "m.matlas"));
}

class PlausibilityLayerTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-plausibility-layer");
    model_ = build(dir_->path() / "gentle", gentle_catalog());
    // Sharp lobes on a coarse table: some inputs' albedo is above 1.
    bright_ = build(dir_->path() / "bright", random_catalog(7, 21));
  }
  static void TearDownTestSuite() {
    delete model_;
    delete bright_;
    delete dir_;
  }
  static test::TempDir* dir_;
  static Model* model_;   ///< every input plausible
  static Model* bright_;  ///< some are not
};
test::TempDir* PlausibilityLayerTest::dir_ = nullptr;
Model* PlausibilityLayerTest::model_ = nullptr;
Model* PlausibilityLayerTest::bright_ = nullptr;

/// A plane over the data and well beyond it, so that some cells are far from every material.
LatentPlane wide_plane(const Model& model) {
  const Eigen::VectorXd lo = model.latent_min(), hi = model.latent_max(), span = hi - lo;
  return LatentPlane::rectangle(0.5 * (lo + hi), 0, 1, lo[0] - span[0], hi[0] + span[0], lo[1] - span[1],
                                hi[1] + span[1]);
}

TEST_F(PlausibilityLayerTest, ConvexMixesOfPlausibleInputsFadeLikeTheAlbedoLayer) {
  const PlausibilityProbe probe(*model_, 256);
  ASSERT_EQ(model_->interpolation(), Interpolation::convex);
  ASSERT_LT(model_->material_albedo().maxCoeff(), 1.0) << "the test needs plausible inputs";
  ASSERT_TRUE(plausible_by_construction(*model_, &probe));

  const LatentPlane plane = wide_plane(*model_);
  const int w = 24, h = 24;
  const std::vector<unsigned char> albedo = map_layer_pixels(*model_, plane, w, h, MapLayer::albedo);
  const std::vector<unsigned char> layer = map_layer_pixels(*model_, plane, w, h, MapLayer::plausibility, &probe);
  ASSERT_EQ(layer.size(), albedo.size());
  int shown = 0, hidden = 0;
  for (std::size_t k = 0; k < layer.size(); k += 4) {
    EXPECT_EQ(layer[k + 3], albedo[k + 3]) << "cell " << k / 4 << ": the albedo layer's fade";
    shown += layer[k + 3] == 255;
    hidden += layer[k + 3] == 0;
    if (layer[k + 3] == 0) continue;
    // Plausible cells: the albedo at 0.45 of its sRGB value (not the implausible red).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(layer[k + c], 0.45 * albedo[k + c], 1.0) << "cell " << k / 4;
  }
  EXPECT_GT(shown, 0);
  EXPECT_GT(hidden, 0) << "the plane reaches far from the data";

  // What the layer skips, computed: every cell's convex weights, probed, are plausible.
  const LatentGrid all = latent_grid(*model_, plane, w, h, Interpolation::convex);
  for (const Plausibility& p : probe.batch(all.weights)) EXPECT_EQ(p.violation(), 0.0);
}

TEST_F(PlausibilityLayerTest, ConvexMixesOfImplausibleInputsAreProbedWhereShown) {
  // Convex weights over inputs with albedo above 1: red where a cell mixes them, and the albedo
  // layer's fade far from the data (a mix of the nearest materials there, as plausible as they).
  const PlausibilityProbe probe(*bright_, 256);
  ASSERT_EQ(bright_->interpolation(), Interpolation::convex);
  ASSERT_GT(bright_->material_albedo().maxCoeff(), 1.0) << "the test needs implausible inputs";
  EXPECT_FALSE(probe.inputs_plausible());
  EXPECT_FALSE(plausible_by_construction(*bright_, &probe));
  const LatentPlane plane = wide_plane(*bright_);
  const int w = 24, h = 24;
  const std::vector<unsigned char> albedo = map_layer_pixels(*bright_, plane, w, h, MapLayer::albedo);
  const std::vector<unsigned char> layer = map_layer_pixels(*bright_, plane, w, h, MapLayer::plausibility, &probe);
  // The shown cells: each one's probe of its convex weights (from a full grid) says its colour.
  const LatentGrid all = latent_grid(*bright_, plane, w, h, Interpolation::convex);
  const std::vector<Plausibility> probed = probe.batch(all.weights);
  int red = 0, dimmed = 0;
  for (std::size_t k = 0; k < layer.size(); k += 4) {
    EXPECT_EQ(layer[k + 3], albedo[k + 3]) << "cell " << k / 4 << ": the albedo layer's fade";
    if (layer[k + 3] == 0) continue;
    const bool plausible = probed[k / 4].violation() == 0.0;
    (plausible ? dimmed : red)++;
    if (plausible)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(layer[k + c], 0.45 * albedo[k + c], 1.0) << "cell " << k / 4;
    else
      EXPECT_GT(layer[k], layer[k + 1] + 40) << "cell " << k / 4 << ": red";
  }
  EXPECT_GT(red, 0);
  EXPECT_GT(dimmed, 0);
}

TEST_F(PlausibilityLayerTest, CellsMixingOnlyPlausibleInputsNeedNoProbe) {
  // What lets the layer skip most cells of a convex map with a few implausible inputs: a convex
  // combination of plausible inputs is plausible, so the probe is asked only about the others.
  const PlausibilityProbe probe(*bright_, 256);
  const int n = bright_->count();
  int plausible_inputs = 0;
  for (int i = 0; i < n; ++i) {
    const bool ok = probe(bright_->material_weights(i)).violation() == 0.0;
    EXPECT_EQ(probe.input_plausible(i), ok) << "input " << i;
    EXPECT_EQ(probe.plausible_by_construction(bright_->material_weights(i)), ok) << "input " << i;
    plausible_inputs += ok;
  }
  ASSERT_GT(plausible_inputs, 1) << "the test needs plausible inputs";
  ASSERT_LT(plausible_inputs, n) << "and implausible ones";
  const LatentGrid all = latent_grid(*bright_, wide_plane(*bright_), 24, 24, Interpolation::convex);
  const std::vector<Plausibility> probed = probe.batch(all.weights);
  int skipped = 0;
  for (Eigen::Index k = 0; k < all.weights.cols(); ++k)
    if (probe.plausible_by_construction(all.weights.col(k))) {
      ++skipped;
      EXPECT_EQ(probed[static_cast<std::size_t>(k)].violation(), 0.0) << "cell " << k;
    }
  EXPECT_GT(skipped, 0);
  EXPECT_LT(skipped, all.weights.cols());
  // Not convex: a negative weight, or a sum away from 1, is probed whatever the inputs.
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  int a = -1, b = -1;
  for (int i = 0; i < n; ++i)
    if (probe.input_plausible(i)) (a < 0 ? a : b) = i;
  w[a] = 1.25, w[b] = -0.25;
  EXPECT_FALSE(probe.plausible_by_construction(w));
  w[a] = 0.5, w[b] = 0.49;
  EXPECT_FALSE(probe.plausible_by_construction(w));
  w[b] = 0.5;
  EXPECT_TRUE(probe.plausible_by_construction(w));
}

TEST_F(PlausibilityLayerTest, TheGpsWeightsAreProbedInEveryCell) {
  // The paper's weights leave the simplex: the same inputs, no guarantee, an opaque layer.
  const Model gp = model_->with_interpolation(Interpolation::gp);
  const PlausibilityProbe probe(gp, 256);
  EXPECT_TRUE(probe.inputs_plausible());
  EXPECT_FALSE(plausible_by_construction(gp, &probe));
  const std::vector<unsigned char> layer = map_layer_pixels(gp, wide_plane(gp), 24, 24, MapLayer::plausibility, &probe);
  for (std::size_t k = 3; k < layer.size(); k += 4) EXPECT_EQ(layer[k], 255);
}

}  // namespace
}  // namespace matlas::atlas
