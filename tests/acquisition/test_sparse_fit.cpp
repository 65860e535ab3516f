// Fitting sparse samples on a map, against tables whose answer is known: an input, a point of
// the map, a material off the map (bounded by the projection of its full table).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "acquisition/model_samples.h"
#include "acquisition_test_model.h"
#include "formats/merl_file.h"
#include "manifold/project.h"
#include "support/error_of.h"

namespace matlas::acquisition {
namespace {

using test::AcquisitionModel;

/// One sample at the centre of every bin whose directions are above the horizon.
std::vector<MeasuredSample> every_bin(const BrdfTable& table) {
  std::vector<MeasuredSample> out;
  const MerlDims& d = table.dims();
  for (int i = 0; i < d.theta_h; ++i)
    for (int j = 0; j < d.theta_d; ++j)
      for (int k = 0; k < d.phi_d; ++k) {
        const DirectionPair pair = from_half_diff(bin_centre(d, i, j, k));
        if (pair.wi.z() <= 1e-3 || pair.wo.z() <= 1e-3) continue;
        MeasuredSample s;
        s.wi = pair.wi;
        s.wo = pair.wo;
        for (int c = 0; c < 3; ++c) s.value[c] = table.value(c, d.flat(i, j, k));
        s.measured = true;
        out.push_back(s);
      }
  return out;
}

TEST(SparseFit, SamplesOfAnInputLandOnItsPoint) {
  const Model& m = *AcquisitionModel::get().model;
  for (int i : {0, 5, 11}) {
    const BrdfTable truth = read_merl(AcquisitionModel::get().paths[static_cast<std::size_t>(i)]);
    const ModelFit f = fit_samples(m, test::sample_table(truth, 20, 10 + static_cast<unsigned>(i)), {});
    EXPECT_EQ(f.fit.best_input, i);
    EXPECT_LT(test::acquisition_error(m.table(f.weights), truth, m), 1e-3) << i;
    EXPECT_LT(f.fit.variance, 1e-3);
    EXPECT_TRUE(f.fit.outliers.empty());
    EXPECT_TRUE(f.unusable.empty());
  }
}

TEST(SparseFit, SamplesOfAMapPointReproduceItsTable) {
  const Model& m = *AcquisitionModel::get().model;
  const Eigen::VectorXd x0 = 0.5 * (m.latent().row(2) + m.latent().row(7)).transpose();
  const BrdfTable truth = m.table(m.weights(x0));
  const ModelFit f = fit_samples(m, test::sample_table(truth, 30, 3), {});
  EXPECT_LT(test::acquisition_error(m.table(f.weights), truth, m), 2e-3);
  EXPECT_LT(f.fit.residual.cwiseAbs().maxCoeff(), 1e-3);
  // The latent uncertainty is small where the samples pin the point down and positive definite.
  EXPECT_GT(f.fit.latent_covariance.determinant(), 0);
}

TEST(SparseFit, AMaterialOffTheMapIsBoundedByItsProjection) {
  const Model& m = *AcquisitionModel::get().model;
  for (auto [a, b] : {std::pair{0.5, 0.5}, std::pair{0.15, 0.9}}) {
    const BrdfTable truth = test::smooth_table(a, b);
    const Projection p = project_material(m, truth);
    // The projection is the best point of the map in L2 over the whole table: no fit does better.
    // Fitted in the same space (linear) from many samples, a fit comes close to it; from 40
    // samples in the layout's cube-root space, within a few times it.
    SparseFitOptions linear;
    linear.transform = LayoutTransform{};
    linear.robust = false;
    linear.combination = false;  // the map point alone (a combination of inputs can do better)
    const double dense = test::acquisition_error(m.table(fit_samples(m, every_bin(truth), linear).weights), truth, m);
    EXPECT_GE(dense, p.relative_error * (1 - 1e-6));
    EXPECT_LT(dense, 1.1 * p.relative_error + 1e-5) << a << "," << b << " projection " << p.relative_error;
    SparseFitOptions map_only;
    map_only.combination = false;
    const double sparse = test::acquisition_error(m.table(fit_samples(m, test::sample_table(truth, 40, 7), map_only).weights), truth, m);
    EXPECT_GE(sparse, p.relative_error * (1 - 1e-6));
    EXPECT_LT(sparse, 4 * p.relative_error + 1e-3) << a << "," << b << " projection " << p.relative_error;
  }
}

TEST(SparseFit, ACombinationOfInputsIsChosenWhereHeldOutSamplesSayItPredictsBetter) {
  const Model& m = *AcquisitionModel::get().model;
  // Half of input 1 and half of input 10: off the q = 2 map, inside the inputs' hull.
  const BrdfTable a = read_merl(AcquisitionModel::get().paths[1]), b = read_merl(AcquisitionModel::get().paths[10]);
  BrdfTable truth = a;
  for (std::size_t v = 0; v < truth.size(); ++v) {
    const int c = static_cast<int>(v / truth.bins());
    truth.set_value(c, v % truth.bins(), 0.5 * (a.value(c, v % truth.bins()) + b.value(c, v % truth.bins())));
  }
  const auto samples = test::sample_table(truth, 60, 4);
  SparseFitOptions map_only;
  map_only.combination = false;
  const ModelFit on_map = fit_samples(m, samples, map_only);
  const ModelFit combined = fit_samples(m, samples, {});
  ASSERT_TRUE(combined.fit.combined);
  EXPECT_TRUE(std::isfinite(combined.fit.combination_strength));
  EXPECT_GE(combined.fit.coefficients.minCoeff(), -1e-12);  // convex
  EXPECT_NEAR(combined.fit.coefficients.sum(), 1, 1e-9);
  const double e_map = test::acquisition_error(m.table(on_map.weights), truth, m);
  const double e_combined = test::acquisition_error(m.table(combined.weights), truth, m);
  EXPECT_LT(e_combined, 0.5 * e_map) << e_map;
  // Samples of an input itself: the map point (exact) predicts as well as anything.
  const ModelFit input = fit_samples(m, test::sample_table(a, 30, 2), {});
  EXPECT_LT(test::acquisition_error(m.table(input.weights), a, m), 1e-3);
}

TEST(SparseFit, TenPercentOfSamplesCorruptedTenfoldBarelyMoveTheFit) {
  const Model& m = *AcquisitionModel::get().model;
  const BrdfTable truth = test::smooth_table(0.4, 0.3);
  std::vector<MeasuredSample> samples = test::sample_table(truth, 40, 21);
  const double clean = test::acquisition_error(m.table(fit_samples(m, samples, {}).weights), truth, m);
  for (int k = 0; k < 4; ++k) samples[static_cast<std::size_t>(9 * k + 3)].value *= 10;
  const ModelFit f = fit_samples(m, samples, {});
  const double corrupt = test::acquisition_error(m.table(f.weights), truth, m);
  EXPECT_LT(corrupt, 1.25 * clean + 1e-3) << "clean " << clean;
  for (int k = 0; k < 4; ++k)
    EXPECT_NE(std::find(f.fit.outliers.begin(), f.fit.outliers.end(), 9 * k + 3), f.fit.outliers.end()) << k;
  // Least squares is pulled away by the same outliers.
  SparseFitOptions squares;
  squares.robust = false;
  const double pulled = test::acquisition_error(m.table(fit_samples(m, samples, squares).weights), truth, m);
  EXPECT_GT(pulled, corrupt);
}

TEST(SparseFit, UncertaintiesWeighTheRows) {
  const Model& m = *AcquisitionModel::get().model;
  const BrdfTable truth = read_merl(AcquisitionModel::get().paths[4]);
  std::vector<MeasuredSample> samples = test::sample_table(truth, 12, 5);
  // Half the samples are another material's values but declared 1000x less certain.
  const BrdfTable other = read_merl(AcquisitionModel::get().paths[9]);
  for (std::size_t k = 0; k < samples.size(); k += 2) {
    const std::size_t bin = bin_of(other.dims(), samples[k].wi, samples[k].wo);
    for (int c = 0; c < 3; ++c) samples[k].value[c] = other.value(c, bin);
    samples[k].sigma = 1000 * samples[k].value + 1;
  }
  for (std::size_t k = 1; k < samples.size(); k += 2) samples[k].sigma = 1e-3 * samples[k].value + 1e-6;
  SparseFitOptions squares;
  squares.robust = false;
  const ModelFit f = fit_samples(m, samples, squares);
  EXPECT_EQ(f.fit.best_input, 4);
  EXPECT_LT(test::acquisition_error(m.table(f.weights), truth, m), 1e-2);
}

TEST(SparseFit, TooFewSamplesSaySo) {
  const Model& m = *AcquisitionModel::get().model;
  const auto samples = test::sample_table(m.table(m.material_weights(0)), 2, 1);
  const std::string message = test::error_of([&] { fit_samples(m, samples, {}); });
  EXPECT_NE(message.find("2 measured samples cannot place a point on a map of dimension 2"), std::string::npos)
      << message;
  std::vector<MeasuredSample> planned = samples;
  for (auto& s : planned) s.measured = false;
  EXPECT_NE(test::error_of([&] { fit_samples(m, planned, {}); }).find("no measured samples"), std::string::npos);
}

TEST(SparseFit, TheTransformIsSignedAndCosineWeighted) {
  const LayoutTransform cbrt{LayoutTransform::Map::cube_root, true};
  EXPECT_DOUBLE_EQ(transform_value(cbrt, 8.0, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(transform_value(cbrt, -8.0, 0.5), -1.0);
  const LayoutTransform log{LayoutTransform::Map::log, false};
  EXPECT_DOUBLE_EQ(transform_value(log, 0.01, 0.3), std::log(2.0));
  EXPECT_DOUBLE_EQ(transform_value(log, -0.01, 0.3), -std::log(2.0));
}

}  // namespace
}  // namespace matlas::acquisition
