// Latent planes, grids, maps and galleries on a small synthetic model.
#include <gtest/gtest.h>

#include <set>

#include "atlas/gallery.h"
#include "atlas/latent_map.h"
#include "atlas/model_basis.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "brdf/catalog.h"
#include "core/check.h"
#include "core/error.h"
#include "formats/image_io.h"
#include "formats/synth_database.h"
#include "gp/posterior.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "render/text.h"
#include "support/temp_dir.h"

namespace matlas::atlas {
namespace {

using render::Environment;
using render::ImageBasis;
using render::RenderSettings;
using render::Scene;
using render::SceneDescription;
using render::text_available;

/// A map of `layer` without labels or legend: only the layer's cells.
MapOptions bare_map(MapLayer layer, int size, int cells) {
  MapOptions o;
  o.layer = layer;
  o.size = size;
  o.cells = cells;
  o.labels = false;
  o.legend = false;
  return o;
}

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

TEST_F(LatentMapTest, GridWeightsAndVariancesAreThePosteriors) {
  const LatentGrid g = latent_grid(*model_, LatentPlane::automatic(*model_), 5, 4);
  ASSERT_EQ(g.points.rows(), 20);
  ASSERT_EQ(g.weights.cols(), 20);
  ASSERT_EQ(g.variance.size(), 20);
  for (int k : {0, 7, 19}) {
    EXPECT_LT((g.weights.col(k) - model_->weights(g.points.row(k).transpose())).norm(), 1e-9);
    EXPECT_NEAR(g.variance[k], model_->variance(g.points.row(k).transpose()), 1e-9);
  }
  // Row 0 is the top of the picture (largest v).
  EXPECT_GT(g.points(0, 1), g.points(15, 1));
}

TEST_F(LatentMapTest, GridWeightsEqualThePerPointWeightsAtEveryCell) {
  // The grid solves the convex weights of each cell from its neighbour's (serpentine order, odd
  // rows turned back): the same as Model::weights point by point, at every cell of a grid that
  // reaches far from the data and has a material on a cell centre. The small grid's GP weights
  // come point by point, the large one's through the kernel's low-rank lines
  // (GpPosterior::predict_grid; its rank checked below).
  ASSERT_EQ(model_->interpolation(), Interpolation::convex);
  const Eigen::VectorXd x0 = model_->latent().row(3).transpose();
  const Eigen::VectorXd span = model_->latent_max() - model_->latent_min();
  for (const int scale : {1, 5}) {
    const int cols = 13 * scale, rows = 9 * scale;  // odd: the last row runs right to left
    const double du = 3.0 * span[0] / 13, dv = 3.0 * span[1] / 9;
    const LatentPlane plane = LatentPlane::rectangle(x0, 0, 1, x0[0] - 6.5 * du, x0[0] + 6.5 * du, x0[1] - 4.5 * dv,
                                                     x0[1] + 4.5 * dv);
    const LatentGrid g = latent_grid(*model_, plane, cols, rows);
    double far = 0;
    for (Eigen::Index k = 0; k < g.points.rows(); ++k) {
      const Eigen::VectorXd x = g.points.row(k).transpose();
      EXPECT_LT((g.weights.col(k) - model_->weights(x)).cwiseAbs().maxCoeff(), 1e-10) << "cell " << k;
      EXPECT_NEAR(g.variance[k], model_->variance(x), 1e-11) << "cell " << k;
      far = std::max(far, g.variance[k]);
    }
    EXPECT_GT(far, 0.9) << "the grid should reach far from the data";
    const Eigen::Index centre = (rows / 2) * cols + cols / 2;  // material 3's cell
    EXPECT_LT((g.points.row(centre).transpose() - x0).norm(), 1e-12);
    EXPECT_LT((g.weights.col(centre) - Eigen::VectorXd::Unit(model_->count(), 3)).cwiseAbs().maxCoeff(), 1e-9);
    const gp::GpPosterior::Batch b = model_->posterior().predict_grid(
        {plane.origin, plane.axis_u, plane.axis_v, plane.cell_u(cols), plane.cell_v(rows)});
    EXPECT_EQ(b.rank > 0, scale > 1) << "grid " << cols << " x " << rows;
  }
}

TEST_F(LatentMapTest, PlausibilityCellsDoNotDependOnHowTheGridIsSplit) {
  // The plausibility layer is computed in blocks of cells in parallel: each cell's colour is the
  // one the same cell gets alone.
  const LatentGrid g = latent_grid(*model_, LatentPlane::automatic(*model_), 40, 30);
  const PlausibilityProbe probe(*model_, 256);
  const LayerCells all = layer_cells(*model_, g, MapLayer::plausibility, {}, &probe);
  for (Eigen::Index k : {0, 511, 512, 700, 1023, 1024, 1199}) {
    LatentGrid one;
    one.cols = one.rows = 1;
    one.points = g.points.row(k);
    one.weights = g.weights.col(k);
    one.variance = g.variance.segment(k, 1);
    const LayerCells alone = layer_cells(*model_, one, MapLayer::plausibility, {}, &probe);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(all.colour[static_cast<std::size_t>(k)][c], alone.colour[0][c], 1e-12) << k;
  }
}

TEST_F(LatentMapTest, AlbedoAndVarianceLayersColourTheGrid) {
  const LatentPlane plane = LatentPlane::automatic(*model_);
  MapOptions o = bare_map(MapLayer::albedo, 64, 8);
  o.style.fade_from = 2, o.style.fade_to = 3;  // no "no data" fade: the raw albedo everywhere
  const Image albedo = render_latent_map(*model_, plane, o);
  const auto [w, h] = map_size(plane, 64);
  ASSERT_EQ(albedo.width, w);
  ASSERT_EQ(albedo.height, h);
  const LatentGrid g = latent_grid(*model_, plane, static_cast<int>(std::lround(8.0 * w / 64)),
                                   static_cast<int>(std::lround(8.0 * h / 64)));
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
  GalleryStats stats;
  pick_gallery(*model_, o, &stats);
  const nlohmann::json key = gallery_key(*model_, a, stats);
  ASSERT_EQ(key["cells"].size(), 8u);
  EXPECT_EQ(key["cells"][0]["cell"], 1);
  EXPECT_EQ(key["interpolation"], to_string(model_->interpolation()));  // the mode of the model
  EXPECT_GT(key["selection"]["candidates"].get<int>(), 0);
  o.real = 100;
  EXPECT_THROW(pick_gallery(*model_, o), Error);
  // The image layer of the map composes thumbnails from the basis.
  MapOptions m;
  m.layer = MapLayer::image;
  m.size = 32;
  m.thumbnails = 2;
  m.basis = &basis;
  m.labels = false;
  const LatentPlane plane = LatentPlane::automatic(*model_);
  const Image thumbs = render_latent_map(*model_, plane, m);
  EXPECT_EQ(std::max(thumbs.width, thumbs.height - 22), 32);  // plus the legend's row
}

TEST_F(LatentMapTest, TheFrameIsTheDataBoxPlusTheStatedMargin) {
  const Eigen::VectorXd mean = model_->latent().colwise().mean().transpose();
  for (const double margin : {0.0, 0.05, 0.2}) {
    for (const LatentPlane& p : {LatentPlane::from_dims(*model_, 0, 1, mean, margin), LatentPlane::pca(*model_, mean, margin)}) {
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
      for (int i = 0; i < model_->count(); ++i) {
        const Eigen::Vector2d uv = p.project(model_->latent().row(i).transpose());
        u0 = std::min(u0, uv.x()), u1 = std::max(u1, uv.x()), v0 = std::min(v0, uv.y()), v1 = std::max(v1, uv.y());
      }
      const double pad = margin * std::max(u1 - u0, v1 - v0);
      // Every point inside with at least the margin; the longer side exactly the data plus margins
      // (no empty space beyond the stated margin), the shorter one widened only to keep 1:3.
      EXPECT_LE(p.u_min, u0 - pad + 1e-12);
      EXPECT_GE(p.u_max, u1 + pad - 1e-12);
      EXPECT_LE(p.v_min, v0 - pad + 1e-12);
      EXPECT_GE(p.v_max, v1 + pad - 1e-12);
      const double du = p.u_max - p.u_min, dv = p.v_max - p.v_min;
      if (u1 - u0 >= v1 - v0) {
        EXPECT_NEAR(du, u1 - u0 + 2 * pad, 1e-9);
        EXPECT_NEAR(dv, std::max(v1 - v0 + 2 * pad, du / 3), 1e-9);
      } else {
        EXPECT_NEAR(dv, v1 - v0 + 2 * pad, 1e-9);
        EXPECT_NEAR(du, std::max(u1 - u0 + 2 * pad, dv / 3), 1e-9);
      }
      // The picture has the plane's aspect.
      const auto [w, h] = map_size(p, 300);
      EXPECT_EQ(std::max(w, h), 300);
      EXPECT_NEAR(static_cast<double>(w) / h, du / dv, 0.02 * du / dv);
    }
  }
}

TEST_F(LatentMapTest, TheCoreFrameKeepsAtLeastHalfAndCountsTheRest) {
  LatentPlane p = LatentPlane::automatic(*model_);
  // The count returned is the materials outside the new frame; the frame only shrinks.
  const int outside = frame_core(*model_, p, 0.1);
  int counted = 0;
  for (int i = 0; i < model_->count(); ++i) {
    const Eigen::Vector2d uv = p.project(model_->latent().row(i).transpose());
    counted += uv.x() < p.u_min || uv.x() > p.u_max || uv.y() < p.v_min || uv.y() > p.v_max;
  }
  EXPECT_EQ(outside, counted);
  EXPECT_LE(outside, model_->count() / 2);
  const LatentPlane all = LatentPlane::automatic(*model_);
  EXPECT_LE(p.u_max - p.u_min, all.u_max - all.u_min + 1e-12);
}

TEST_F(LatentMapTest, MapLabelsDoNotOverlapAndFarRegionsAreMarkedAsNoData) {
  const LatentPlane plane = LatentPlane::automatic(*model_);
  MapOptions o;
  o.size = 160;  // small: labels must be dropped to avoid overlaps
  const MapLabels labels = map_labels(*model_, plane, o);
  ASSERT_EQ(labels.labels.size(), static_cast<std::size_t>(model_->count()));
  for (std::size_t i = 0; i < labels.labels.size(); ++i)
    for (std::size_t j = i + 1; j < labels.labels.size(); ++j)
      if (labels.labels[i].shown && labels.labels[j].shown) {
        EXPECT_FALSE(render::overlaps(labels.labels[i].box, labels.labels[j].box));
      }
  if (text_available()) {
    EXPECT_GT(labels.shown(), 0);
  }

  // A plane far larger than the data: its corners are far from every point (variance near 1) and
  // show the "no data" hatching, not the database mean's albedo; the data's cells show the albedo.
  LatentPlane wide = plane;
  const double span = plane.u_max - plane.u_min;
  wide.u_min -= 20 * span, wide.u_max += 20 * span, wide.v_min -= 20 * span, wide.v_max += 20 * span;
  o = bare_map(MapLayer::albedo, 64, 64);
  const Image map = render_latent_map(*model_, wide, o);
  const auto [mw, mh] = map_size(wide, 64);
  ASSERT_EQ(map.width, mw);
  ASSERT_EQ(map.height, mh);
  ASSERT_GT(model_->variance(wide.point(wide.u_min, wide.v_min)), 0.9);
  for (const auto& [x, y] : {std::pair{0, mh - 1}, std::pair{1, mh - 2}, std::pair{5, mh - 1}, std::pair{mw - 1, 0}})
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(map.pixel(x, y)[c], unknown_colour(x, y)[c], 1e-6);
  EXPECT_NE(unknown_colour(0, 0)[0], unknown_colour(4, 0)[0]);  // hatched, not flat
  EXPECT_EQ(uncertainty_fade(0.2, 0.5, 0.9), 0.0);
  EXPECT_EQ(uncertainty_fade(0.95, 0.5, 0.9), 1.0);
  EXPECT_NEAR(uncertainty_fade(0.7, 0.5, 0.9), 0.5, 1e-12);
  // With a legend the picture grows by its strip.
  o.legend = true;
  EXPECT_GT(render_latent_map(*model_, wide, o).height, mh);
}

TEST_F(LatentMapTest, TheVarianceRampIsTheBrowsersLegendSwatch) {
  // web/src/style.css draws the legend of the variance layer with these five sRGB8 stops (to the
  // rounding of a stop at .5: 0.90 * 255 = 229.5 there).
  const int stops[5][3] = {{13, 15, 26}, {46, 41, 97}, {140, 51, 115}, {235, 115, 77}, {252, 230, 153}};
  for (int i = 0; i < 5; ++i) {
    const Eigen::Array3d c = colour_map(i / 4.0);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(255.0 * srgb_encode(static_cast<float>(c[k])), stops[i][k], 0.5 + 1e-3) << i << " " << k;
  }
  // Ordered from dark (at the data) to light (far away).
  EXPECT_LT(colour_map(0.1).sum(), colour_map(0.6).sum());
}

TEST_F(LatentMapTest, LayerNamesAreOneSetForTheCommandAndTheServer) {
  for (MapLayer l : {MapLayer::albedo, MapLayer::variance, MapLayer::plausibility, MapLayer::image})
    EXPECT_EQ(map_layer_from_name(to_string(l), "--layer"), l);
  try {
    map_layer_from_name("height", "--layer");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "--layer 'height': expected albedo, variance, plausibility or image");
  }
}

TEST_F(LatentMapTest, ServerLayersArePerPointQueriesOnTheRectangle) {
  // The server's albedo layer: every pixel centre of the rectangle, queried point by point.
  const Eigen::VectorXd base = model_->latent().row(2).transpose();
  const Eigen::VectorXd lo = model_->latent_min(), hi = model_->latent_max();
  const double x0 = lo[0], x1 = hi[0], y0 = lo[2], y1 = hi[2];
  const int w = 6, h = 5;
  const LatentPlane plane = LatentPlane::rectangle(base, 0, 2, x0, x1, y0, y1);
  const std::vector<unsigned char> px = map_layer_pixels(*model_, plane, w, h, MapLayer::albedo);
  ASSERT_EQ(px.size(), static_cast<std::size_t>(w * h * 4));
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      Eigen::VectorXd x = base;
      x[0] = x0 + (x1 - x0) * (col + 0.5) / w;
      x[2] = y1 - (y1 - y0) * (row + 0.5) / h;  // top row first
      const Rgb a = model_->albedo_curve(model_->weights(x)).front();
      const unsigned char* p = px.data() + 4 * (row * w + col);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(p[c], 255.0 * srgb_encode(static_cast<float>(std::clamp(a[c], 0.0, 1.0))), 0.5 + 1e-6);
      EXPECT_NEAR(p[3], 255.0 * (1.0 - uncertainty_fade(model_->variance(x), kFadeFrom, kFadeTo)), 0.5 + 1e-6);
    }
  EXPECT_THROW(LatentPlane::rectangle(base, 0, 0, 0, 1, 0, 1), Error);
  EXPECT_THROW(LatentPlane::rectangle(base, 0, 1, 1, 0, 0, 1), Error);
  // No probe: a caller's bug (the server and `matlas map` always pass one), not a user's error.
  EXPECT_THROW(map_layer_pixels(*model_, plane, w, h, MapLayer::plausibility), InternalError);
}

TEST_F(LatentMapTest, TheAlbedoLayerProjectsOnlyTheCellsItShows) {
  // A strip from material 0 out to far from the data: cells below the fade's end have the convex
  // weights of the point (and its albedo); cells beyond it are fully transparent, their weights
  // left the GP's (never shown, not worth a projection).
  ASSERT_EQ(model_->interpolation(), Interpolation::convex);
  const Eigen::VectorXd x0 = model_->latent().row(0).transpose();
  const Eigen::VectorXd span = model_->latent_max() - model_->latent_min();
  const LatentPlane strip = LatentPlane::rectangle(x0, 0, 1, x0[0], x0[0] + 3 * span[0], x0[1] - 0.05 * span[1],
                                                   x0[1] + 0.05 * span[1]);
  const int w = 12, h = 2;
  const LatentGrid g = latent_grid(*model_, strip, w, h, Interpolation::convex, kFadeTo);
  const std::vector<unsigned char> px = map_layer_pixels(*model_, strip, w, h, MapLayer::albedo);
  int shown = 0, hidden = 0;
  for (int cell = 0; cell < w * h; ++cell) {
    const Eigen::VectorXd x = g.points.row(cell).transpose();
    const unsigned char* p = px.data() + 4 * cell;
    if (model_->variance(x) < kFadeTo) {
      ++shown;
      EXPECT_LE((g.weights.col(cell) - model_->weights(x)).cwiseAbs().maxCoeff(), 1e-10) << "cell " << cell;
      const Rgb a = model_->albedo_curve(model_->weights(x)).front();
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(p[c], 255.0 * srgb_encode(static_cast<float>(std::clamp(a[c], 0.0, 1.0))), 0.5 + 1e-6);
    } else {
      ++hidden;
      EXPECT_EQ(p[3], 0) << "cell " << cell;
      EXPECT_LE((g.weights.col(cell) - model_->weights(x, Interpolation::gp)).cwiseAbs().maxCoeff(), 1e-10);
    }
  }
  EXPECT_GT(shown, 0);
  EXPECT_GT(hidden, 0);
}

TEST(MapLegend, SaysWhatAPointFarFromTheDataIsUnderEachInterpolation) {
  // Far from the data the GP's weights fall to 0 (the database mean) but convex weights still
  // sum to 1: the legend must not call a convex model's far points the mean.
  EXPECT_STREQ(far_from_data(Interpolation::gp), "only the database mean");
  EXPECT_STREQ(far_from_data(Interpolation::convex), "a mix of the nearest materials");
}

TEST_F(LatentMapTest, TheVarianceLayerIsTheSameInEveryInterpolationMode) {
  // The variance layer takes the GP's weights (it uses none): the same pixels as the posterior
  // variance point by point, whatever the model's mode.
  const LatentPlane plane = LatentPlane::automatic(*model_);
  EXPECT_EQ(layer_interpolation(*model_, MapLayer::variance), Interpolation::gp);
  ASSERT_EQ(model_->interpolation(), Interpolation::convex);
  EXPECT_EQ(layer_interpolation(*model_, MapLayer::albedo), Interpolation::convex);
  const int w = 5, h = 4;
  const std::vector<unsigned char> px = map_layer_pixels(*model_, plane, w, h, MapLayer::variance);
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      const Eigen::VectorXd x = plane.point(plane.u_min + (col + 0.5) / w * (plane.u_max - plane.u_min),
                                            plane.v_max - (row + 0.5) / h * (plane.v_max - plane.v_min));
      const Eigen::Array3d c = colour_map(model_->variance(x));
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(px[4 * static_cast<std::size_t>(row * w + col) + k], 255.0 * srgb_encode(static_cast<float>(c[k])),
                    0.5 + 1e-6);
    }
}

TEST_F(LatentMapTest, AlbedoLayerIsTransparentFarFromTheDataAndOpaqueAtIt) {
  // A rectangle around material 0 (tiny: every cell at the data) and one in the domain's corner.
  const Eigen::VectorXd lo = model_->latent_min(), hi = model_->latent_max(), x0 = model_->latent().row(0).transpose();
  const double e = 1e-6 * (hi - lo).maxCoeff();
  const auto near = map_layer_pixels(*model_, LatentPlane::rectangle(x0, 0, 1, x0[0] - e, x0[0] + e, x0[1] - e, x0[1] + e),
                                     4, 4, MapLayer::albedo);
  ASSERT_EQ(near.size(), 64u);
  for (std::size_t k = 3; k < near.size(); k += 4) EXPECT_EQ(near[k], 255);
  const Eigen::VectorXd span = hi - lo;
  const LatentPlane corner = LatentPlane::rectangle(x0, 0, 1, lo[0] - span[0], lo[0] - 0.8 * span[0], lo[1] - span[1],
                                                    lo[1] - 0.8 * span[1]);
  ASSERT_GT(model_->variance(corner.point(corner.u_min, corner.v_min)), 0.9) << "the test needs a corner far from the data";
  const auto far = map_layer_pixels(*model_, corner, 4, 4, MapLayer::albedo);
  EXPECT_EQ(far[(3 * 4 + 0) * 4 + 3], 0) << "bottom-left cell, at the corner";
  // Opaque: the variance layer, and the plausibility layer of the GP's weights (that of convex
  // weights fades like the albedo layer: test_plausibility_layer.cpp).
  const Model gp = model_->with_interpolation(Interpolation::gp);
  const PlausibilityProbe probe(gp, 256);
  for (MapLayer l : {MapLayer::variance, MapLayer::plausibility}) {
    const auto opaque = map_layer_pixels(gp, corner, 4, 4, l, &probe);
    for (std::size_t k = 3; k < opaque.size(); k += 4) EXPECT_EQ(opaque[k], 255);
  }
}

TEST_F(LatentMapTest, ThePlausibilityPictureIsTheServersLayer) {
  // One pipeline: the command's picture of the plausibility layer shows, in each cell, the
  // colour the server's layer gives the same grid.
  const LatentPlane plane = LatentPlane::automatic(*model_);
  const MapOptions o = bare_map(MapLayer::plausibility, 64, 8);
  const Image picture = render_latent_map(*model_, plane, o);
  const auto [w, h] = map_size(plane, 64);
  const int cx = static_cast<int>(std::lround(8.0 * w / 64)), cy = static_cast<int>(std::lround(8.0 * h / 64));
  const PlausibilityProbe probe(*model_, 256);
  const std::vector<unsigned char> layer = map_layer_pixels(*model_, plane, cx, cy, MapLayer::plausibility, &probe);
  for (int cell : {0, cx * cy / 2, cx * cy - 1}) {
    const int x = (cell % cx) * w / cx + 1, y = (cell / cx) * h / cy + 1;  // a pixel inside the cell
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(255.0 * srgb_encode(picture.pixel(x, y)[c]), layer[4 * static_cast<std::size_t>(cell) + c], 0.5 + 1e-3);
  }
}

TEST_F(LatentMapTest, GalleryCellsRefineToTheTargetError) {
  // With a target error every cell is refined until its estimated error is under it: each agrees
  // with a long render of its material to about the target (the corner's number left out).
  GalleryOptions o;
  o.random = 1;
  o.real = 1;
  const std::vector<GalleryEntry> entries = pick_gallery(*model_, o);
  ASSERT_EQ(entries.size(), 2u);
  const Scene scene(SceneDescription{}, std::nullopt, Environment(test::synthetic_environment()));
  RenderSettings s;
  s.width = s.height = 48;
  s.spp = 4096;
  std::vector<render::RefinementState> refined;
  const Image grid = render_gallery(*model_, entries, &scene, &s, nullptr, null_progress(), 0.02, &refined);
  ASSERT_EQ(refined.size(), entries.size());
  for (const render::RefinementState& st : refined) {
    EXPECT_LE(st.relative_error, 0.02);
    EXPECT_LT(st.spp, 4096);  // stopped by the target, not the cap
  }
  const int gap = 2;  // max(2, 48 / 64)
  RenderSettings long_render = model_render_settings(*model_, s);
  long_render.spp = 2048;
  long_render.seed = 12345;
  const std::vector<float> coverage = render::object_coverage(scene, long_render);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const GalleryEntry& e = entries[k];
    const Eigen::VectorXd w = e.real ? model_->material_weights(model_->index_of(e.name)) : model_->weights(e.x);
    const Image reference = render::render(scene, ModelTableMaterial(*model_, w), long_render);
    const int ox = gap + static_cast<int>(k) * (48 + gap), oy = gap;
    double squares = 0, signal = 0;
    for (int y = 16; y < 48; ++y)  // below the number
      for (int x = 0; x < 48; ++x) {
        if (coverage[static_cast<std::size_t>(y * 48 + x)] < 1.0f) continue;
        for (int c = 0; c < 3; ++c) {
          const double d = grid.pixel(ox + x, oy + y)[c] - reference.pixel(x, y)[c];
          squares += d * d;
          signal += static_cast<double>(reference.pixel(x, y)[c]) * reference.pixel(x, y)[c];
        }
      }
    EXPECT_LT(std::sqrt(squares / signal), 0.05) << "cell " << k + 1;
  }
}

}  // namespace
}  // namespace matlas::atlas
