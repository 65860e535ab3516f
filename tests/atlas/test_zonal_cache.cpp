// The zonal coefficients cached beside a model (atlas/zonal_cache.h): the batched projection
// equals the per-table one; a second request loads what the first computed; a rebuilt model (other
// inputs) and a truncated cache file are recomputed, with a note saying why, and rewritten.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "atlas/model_zonal.h"
#include "atlas/zonal_cache.h"
#include "brdf/catalog.h"
#include "core/error.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "support/temp_dir.h"

namespace matlas::atlas {
namespace {

const MerlDims kDims{16, 16, 32};
const zonal::ProjectionSettings kSettings{4, 6, 32, 64};

void build(const std::filesystem::path& dir, int materials, unsigned seed, const std::filesystem::path& model) {
  std::filesystem::remove_all(dir);
  write_database(dir, random_catalog(materials, seed), null_progress(), kDims);
  BuildOptions options;
  options.dim = 2;
  build_model(MaterialSet::open({dir}), options, model);
}

double largest(const zonal::CoefficientSet& s) {
  double m = 0;
  for (const auto& c : s.materials)
    for (double v : c.values) m = std::max(m, std::abs(v));
  return m;
}

/// Largest |a - b| over every material and the mean.
double difference(const zonal::CoefficientSet& a, const zonal::CoefficientSet& b) {
  EXPECT_EQ(a.materials.size(), b.materials.size());
  double d = 0;
  for (std::size_t i = 0; i < a.materials.size(); ++i)
    for (std::size_t v = 0; v < a.materials[i].values.size(); ++v)
      d = std::max(d, std::abs(a.materials[i].values[v] - b.materials[i].values[v]));
  for (std::size_t v = 0; v < a.mean->values.size(); ++v) d = std::max(d, std::abs(a.mean->values[v] - b.mean->values[v]));
  return d;
}

TEST(ZonalCache, BatchedProjectionEqualsTheProjectionOfEachTable) {
  test::TempDir dir("matlas-zonal-cache");
  build(dir.path() / "db", 4, 7, dir.path() / "m.matlas");
  const Model model = Model::open(dir.path() / "m.matlas");
  const zonal::CoefficientSet set = model_coefficients(model, kSettings);
  const zonal::ZonalProjector projector(kSettings, kDims);
  const double scale = largest(set);
  ASSERT_GT(scale, 0.0);
  for (int i = 0; i < model.count(); ++i) {
    const zonal::ZonalCoefficients own = projector.project(model.table(model.material_weights(i)));
    for (std::size_t v = 0; v < own.values.size(); ++v)
      ASSERT_NEAR(set.materials[static_cast<std::size_t>(i)].values[v], own.values[v], 1e-12 * scale) << i << " " << v;
  }
  const zonal::ZonalCoefficients mean = projector.project(model.table(Eigen::VectorXd::Zero(model.count())));
  for (std::size_t v = 0; v < mean.values.size(); ++v) ASSERT_NEAR(set.mean->values[v], mean.values[v], 1e-12 * scale);
}

TEST(ZonalCache, SecondRequestLoadsWhatTheFirstComputed) {
  test::TempDir dir("matlas-zonal-cache");
  build(dir.path() / "db", 4, 7, dir.path() / "m.matlas");
  const Model model = Model::open(dir.path() / "m.matlas");
  const auto cache = zonal_cache_path(model.path(), kSettings.bands);
  EXPECT_EQ(cache.filename(), "m.matlas.zonal-L4");
  const CachedCoefficients first = cached_model_coefficients(model, kSettings, cache);
  EXPECT_FALSE(first.loaded);
  EXPECT_NE(first.note.find("no cache"), std::string::npos) << first.note;
  EXPECT_NE(first.note.find("written"), std::string::npos) << first.note;
  ASSERT_TRUE(std::filesystem::exists(cache));
  const CachedCoefficients second = cached_model_coefficients(model, kSettings, cache);
  EXPECT_TRUE(second.loaded) << second.note;
  EXPECT_EQ(second.set.names, model.names());
  EXPECT_LT(difference(first.set, second.set), 1e-6 * largest(first.set));  // float32 storage
  // Other settings (more bands) do not take this cache for theirs.
  zonal::ProjectionSettings other = kSettings;
  other.theta_o_count = 8;
  const CachedCoefficients third = cached_model_coefficients(model, other, cache);
  EXPECT_FALSE(third.loaded);
  EXPECT_NE(third.note.find("stale"), std::string::npos) << third.note;
  // Nor do the viewer's settings (lobes and a ring floor) with only the ring floor different: the
  // cache holds the weighted coefficients, and it says which floor.
  zonal::ProjectionSettings viewer = kSettings;
  viewer.lobes = {64.0, 256.0};
  viewer.ring_floor = 0.05;
  EXPECT_FALSE(cached_model_coefficients(model, viewer, cache).loaded);
  EXPECT_TRUE(cached_model_coefficients(model, viewer, cache).loaded);
  zonal::ProjectionSettings floor = viewer;
  floor.ring_floor = 0.1;
  const CachedCoefficients other_floor = cached_model_coefficients(model, floor, cache);
  EXPECT_FALSE(other_floor.loaded);
  EXPECT_EQ(other_floor.set.settings.ring_floor, 0.1);
}

TEST(ZonalCache, RebuiltModelInvalidatesTheCache) {
  test::TempDir dir("matlas-zonal-cache");
  const auto path = dir.path() / "m.matlas";
  build(dir.path() / "db", 4, 7, path);
  zonal::CoefficientSet old;
  {
    const Model model = Model::open(path);
    old = cached_model_coefficients(model, kSettings, zonal_cache_path(path, kSettings.bands)).set;
  }
  build(dir.path() / "db", 4, 8, path);  // same names and count, other materials
  const Model model = Model::open(path);
  const CachedCoefficients c = cached_model_coefficients(model, kSettings, zonal_cache_path(path, kSettings.bands));
  EXPECT_FALSE(c.loaded);
  EXPECT_NE(c.note.find("stale"), std::string::npos) << c.note;
  const zonal::CoefficientSet fresh = model_coefficients(model, kSettings);
  EXPECT_LT(difference(c.set, fresh), 1e-12 * largest(fresh));
  EXPECT_GT(difference(old, fresh), 1e-3 * largest(fresh));  // the old cache would have been wrong
  EXPECT_TRUE(cached_model_coefficients(model, kSettings, zonal_cache_path(path, kSettings.bands)).loaded);
}

TEST(ZonalCache, TruncatedCacheIsRefusedWithItsNameAndRecomputed) {
  test::TempDir dir("matlas-zonal-cache");
  const auto path = dir.path() / "m.matlas";
  build(dir.path() / "db", 4, 7, path);
  const Model model = Model::open(path);
  const auto cache = zonal_cache_path(path, kSettings.bands);
  const zonal::CoefficientSet exact = cached_model_coefficients(model, kSettings, cache).set;
  const auto size = std::filesystem::file_size(cache);
  std::filesystem::resize_file(cache, size / 2);
  try {
    zonal::read_coefficients(cache);
    ADD_FAILURE() << "a truncated cache was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(cache.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  const CachedCoefficients c = cached_model_coefficients(model, kSettings, cache);
  EXPECT_FALSE(c.loaded);
  EXPECT_NE(c.note.find("refused"), std::string::npos) << c.note;
  EXPECT_NE(c.note.find("truncated"), std::string::npos) << c.note;
  EXPECT_LT(difference(c.set, exact), 1e-6 * largest(exact));
  EXPECT_EQ(std::filesystem::file_size(cache), size);  // rewritten whole
  EXPECT_TRUE(cached_model_coefficients(model, kSettings, cache).loaded);
}

TEST(ZonalCache, UnwritableFolderStillAnswers) {
  test::TempDir dir("matlas-zonal-cache");
  build(dir.path() / "db", 3, 7, dir.path() / "m.matlas");
  const Model model = Model::open(dir.path() / "m.matlas");
  const auto cache = dir.path() / "missing-folder" / "m.matlas.zonal-L4";
  const CachedCoefficients c = cached_model_coefficients(model, kSettings, cache);
  EXPECT_FALSE(c.loaded);
  EXPECT_NE(c.note.find("not cached"), std::string::npos) << c.note;
  EXPECT_EQ(c.set.materials.size(), 3u);
}

}  // namespace
}  // namespace matlas::atlas
