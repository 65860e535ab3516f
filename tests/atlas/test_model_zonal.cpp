// The zonal coefficients of a model: a map point's coefficients, made in the viewer as
// mean + sum_i w_i (lambda_i - mean), equal the projection of the model's table at w (for GP
// weights with mixed signs too), and material i's block is the projection of its reconstruction.
#include <gtest/gtest.h>

#include <cmath>

#include "atlas/model_zonal.h"
#include "brdf/catalog.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "support/temp_dir.h"
#include "zonal/shader_layout.h"

namespace matlas::atlas {
namespace {

TEST(ModelZonal, MapPointCoefficientsAreTheProjectionOfTheMapPointsTable) {
  test::TempDir dir("matlas-model-zonal");
  const MerlDims dims{16, 16, 32};
  write_database(dir.path() / "db", random_catalog(5, 3), null_progress(), dims);
  BuildOptions options;
  options.dim = 2;
  build_model(MaterialSet::open({dir.path() / "db"}), options, dir.path() / "m.matlas");
  const Model model = Model::open(dir.path() / "m.matlas");
  const zonal::ProjectionSettings settings{4, 6, 32, 64};
  const zonal::CoefficientSet set = model_coefficients(model, settings);
  ASSERT_EQ(set.materials.size(), 5u);
  ASSERT_TRUE(set.mean.has_value());
  EXPECT_EQ(set.names, model.names());

  // The packed float32 payload of the viewer, combined as the page does.
  const std::vector<float> packed = zonal::pack_coefficients(set);
  const std::size_t block = set.mean->values.size();
  ASSERT_EQ(packed.size(), 6 * block);
  const zonal::ZonalProjector projector(settings, dims);
  const Eigen::VectorXd w = model.weights(Eigen::Vector2d(0.3 * model.latent_min()[0] + 0.7 * model.latent_max()[0],
                                                           0.5 * model.latent_min()[1] + 0.5 * model.latent_max()[1]));
  const zonal::ZonalCoefficients direct = projector.project(model.table(w));
  double largest = 0, worst = 0;
  for (std::size_t v = 0; v < block; ++v) {
    double c = (1.0 - w.sum()) * packed[v];
    for (int i = 0; i < 5; ++i) c += w[i] * packed[(static_cast<std::size_t>(i) + 1) * block + v];
    largest = std::max(largest, std::abs(direct.values[v]));
    worst = std::max(worst, std::abs(c - direct.values[v]));
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-5 * largest);  // float32 storage of the payload
  // Material 2's block is its reconstruction's projection.
  const zonal::ZonalCoefficients own = projector.project(model.table(model.material_weights(2)));
  for (std::size_t v = 0; v < block; v += 7)
    EXPECT_NEAR(packed[3 * block + v], own.values[v], 1e-5 * largest);
}

}  // namespace
}  // namespace matlas::atlas
