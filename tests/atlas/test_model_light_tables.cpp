// The light tables of a model (atlas/model_light_tables.h): material i's is the light table of the
// model's reconstruction of material i (to float16), and a map point's, combined from the stored
// ones, is the light table of the model's table at that point's weights (GP weights of both signs).
#include <gtest/gtest.h>

#include <cmath>

#include "atlas/model_light_tables.h"
#include "brdf/catalog.h"
#include "core/error.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "support/temp_dir.h"

namespace matlas::atlas {
namespace {

double relative_difference(const zonal::LightTable& a, const zonal::LightTable& b) {
  double num = 0, den = 0;
  for (std::size_t v = 0; v < a.values().size(); ++v) {
    num = std::max(num, static_cast<double>(std::abs(a.values()[v] - b.values()[v])));
    den = std::max(den, static_cast<double>(std::abs(b.values()[v])));
  }
  return num / den;
}

TEST(ModelLightTables, MaterialsAndMapPointsAreTheLightTablesOfTheModelsTables) {
  test::TempDir dir("matlas-model-light-tables");
  const MerlDims dims{16, 16, 32};
  write_database(dir.path() / "db", random_catalog(5, 7), null_progress(), dims);
  BuildOptions options;
  options.dim = 2;
  build_model(MaterialSet::open({dir.path() / "db"}), options, dir.path() / "m.matlas");
  const Model model = Model::open(dir.path() / "m.matlas");
  const ModelLightTables tables(model);
  EXPECT_EQ(tables.count(), 5);
  EXPECT_EQ(tables.dims(), (MerlDims{16, 16, 8}));
  for (int i = 0; i < 5; ++i) {
    const zonal::LightTable own = zonal::LightTable::reduce(model.table(model.material_weights(i)));
    EXPECT_LT(relative_difference(tables.table(i), own), 2e-3) << i;  // float16: 2^-11 relative
    EXPECT_LT(relative_difference(tables.at(model.material_weights(i)), own), 2e-3) << i;
  }
  const Eigen::VectorXd w = model.weights(Eigen::Vector2d(0.3 * model.latent_min()[0] + 0.7 * model.latent_max()[0],
                                                           0.6 * model.latent_min()[1] + 0.4 * model.latent_max()[1]),
                                          Interpolation::gp);
  EXPECT_LT(w.minCoeff(), 0.0);  // GP weights: the mean's weight and negative ones take part
  const zonal::LightTable direct = zonal::LightTable::reduce(model.table(w));
  EXPECT_LT(relative_difference(tables.at(w), direct), 5e-3);
  EXPECT_THROW(tables.at(Eigen::VectorXd::Zero(4)), Error);
}

}  // namespace
}  // namespace matlas::atlas
