// The leave-one-out / latent-path harness on a tiny synthetic database (small MERL grid).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <Eigen/SVD>

#include "brdf/catalog.h"
#include "core/error.h"
#include "eval/brdf_distance.h"
#include "eval/combination_pass.h"
#include "eval/layout_study.h"
#include "formats/merl_file.h"
#include "formats/synth_database.h"
#include "manifold/material_set.h"
#include "support/temp_dir.h"

namespace matlas::eval {
namespace {

const MerlDims kTiny{6, 6, 12};

/// 6 random analytic materials plus an exact copy of the third one ("zz-copy").
class TinyDatabase : public ::testing::Test {
protected:
  void SetUp() override {
    write_database(dir_.path(), random_catalog(6, 7), null_progress(), kTiny);
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir_.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::filesystem::copy_file(files[2], dir_ / "zz-copy.binary");
    set_ = std::make_unique<MaterialSet>(MaterialSet::open({dir_.path()}));
    for (std::size_t i = 0; i < set_->size(); ++i) tables_.push_back(read_merl(set_->file(i).path()));
  }
  test::TempDir dir_{"matlas-eval-study"};
  std::unique_ptr<MaterialSet> set_;
  std::vector<BrdfTable> tables_;
};

/// The coefficients of the n materials and, as item n, the midpoint of materials 0 and 1.
Eigen::MatrixXd materials_and_midpoint(Eigen::Index n) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n + 1, n);
  c.topRows(n).setIdentity();
  c(n, 0) = 0.5, c(n, 1) = 0.5;
  return c;
}

TEST_F(TinyDatabase, CombinationPassMatchesDirectDistances) {
  CombinationQuery q;
  const auto n = static_cast<Eigen::Index>(set_->size());
  q.coefficients = materials_and_midpoint(n);
  q.pairs = {{0, 1}, {1, 0}, {3, 3}, {static_cast<int>(n), 0}};
  q.memory_budget = 4096;  // many small blocks
  const CombinationResult r = evaluate_combinations(*set_, q);
  const BrdfDistance direct = brdf_distance(tables_[0], tables_[1]);
  EXPECT_NEAR(r.distances[0].cbrt_cosine, direct.cbrt_cosine, 1e-12 * (1 + direct.cbrt_cosine));
  EXPECT_NEAR(r.distances[0].cosine_rmse, direct.cosine_rmse, 1e-12 * (1 + direct.cosine_rmse));
  EXPECT_EQ(r.distances[0].values, direct.values);
  EXPECT_EQ(r.distances[1].cbrt_cosine, r.distances[0].cbrt_cosine);
  EXPECT_EQ(r.distances[2].cbrt_cosine, 0.0);
  BrdfTable mid(kTiny);
  for (int c = 0; c < 3; ++c)
    for (std::size_t b = 0; b < mid.bins(); ++b)
      mid.set_value(c, b, 0.5 * (tables_[0].value(c, b) + tables_[1].value(c, b)));
  EXPECT_NEAR(r.distances[3].cbrt_cosine, brdf_distance(mid, tables_[0]).cbrt_cosine, 1e-9);
  for (std::size_t i = 0; i < r.negatives.size(); ++i) EXPECT_EQ(r.negatives[i], 0u);
}

TEST_F(TinyDatabase, ThreeSharesOfTheCombinationPassAddUpToTheWholePass) {
  // The shares of a pass split across ranks (CombinationQuery::share): their sums, added as
  // reduce_combinations adds the ranks', finish into the whole pass's distances, and every value
  // is compared once (counts add up exactly).
  CombinationQuery q;
  const auto n = static_cast<Eigen::Index>(set_->size());
  q.coefficients = Eigen::MatrixXd::Identity(n, n);
  q.pairs = {{0, 1}, {2, 4}, {3, 5}};
  q.memory_budget = 4096;
  q.value_stride = 3;
  const CombinationResult whole = evaluate_combinations(*set_, q);
  std::vector<DistanceSums> sums(q.pairs.size());
  std::size_t values = 0;
  for (int part = 0; part < 3; ++part) {
    q.share = {part, 3};
    const CombinationResult r = evaluate_combinations(*set_, q);
    values += r.values;
    EXPECT_GT(r.values, 0u);
    EXPECT_LT(r.values, whole.values);
    for (std::size_t p = 0; p < sums.size(); ++p) {
      sums[p].cbrt_squared += r.sums[p].cbrt_squared;
      sums[p].cosine_squared += r.sums[p].cosine_squared;
      sums[p].values += r.sums[p].values;
    }
  }
  EXPECT_EQ(values, whole.values);
  for (std::size_t p = 0; p < sums.size(); ++p) {
    const BrdfDistance d = sums[p].finish();
    EXPECT_EQ(d.values, whole.distances[p].values);
    EXPECT_NEAR(d.cbrt_cosine, whole.distances[p].cbrt_cosine, 1e-12 * whole.distances[p].cbrt_cosine);
    EXPECT_NEAR(d.cosine_rmse, whole.distances[p].cosine_rmse, 1e-12 * whole.distances[p].cosine_rmse);
  }
}

TEST_F(TinyDatabase, PairsThroughTheMaterialsGramMatchTheDifferences) {
  // gram_items: every pair of two different materials from their Gram matrices, the same
  // distances as by differences to 1e-9; a pair with a combination or of an item with itself
  // still by differences; the ranks' shares add up as before.
  CombinationQuery q;
  const auto n = static_cast<Eigen::Index>(set_->size());
  q.coefficients = materials_and_midpoint(n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) q.pairs.emplace_back(a, b);
  q.pairs.emplace_back(static_cast<int>(n), 0);
  q.memory_budget = 4096;
  const CombinationResult by_difference = evaluate_combinations(*set_, q);
  q.gram_items = static_cast<int>(n);
  const CombinationResult by_gram = evaluate_combinations(*set_, q);
  for (std::size_t p = 0; p < q.pairs.size(); ++p) {
    const BrdfDistance &d = by_difference.distances[p], &g = by_gram.distances[p];
    EXPECT_NEAR(g.cbrt_cosine, d.cbrt_cosine, 1e-9 * d.cbrt_cosine) << "pair " << p;
    EXPECT_NEAR(g.cosine_rmse, d.cosine_rmse, 1e-9 * d.cosine_rmse) << "pair " << p;
    EXPECT_EQ(g.values, d.values) << "pair " << p;
  }
  EXPECT_EQ(by_gram.distances[0].cbrt_cosine, 0.0);  // (0, 0)
  EXPECT_GT(by_gram.distances[1].cbrt_cosine, 0.0);  // (0, 1)
  // Material 2 and its copy (the last one): 0 through the Gram too, whatever its rounding.
  const std::size_t copy_pair = static_cast<std::size_t>(2 * n + n - 1);
  EXPECT_EQ(by_gram.distances[copy_pair].cbrt_cosine, 0.0);
  EXPECT_EQ(by_gram.distances[copy_pair].cosine_rmse, 0.0);
  std::vector<DistanceSums> sums(q.pairs.size());
  for (int part = 0; part < 2; ++part) {
    q.share = {part, 2};
    const CombinationResult r = evaluate_combinations(*set_, q);
    for (std::size_t p = 0; p < sums.size(); ++p) {
      sums[p].cbrt_squared += r.sums[p].cbrt_squared;
      sums[p].cosine_squared += r.sums[p].cosine_squared;
      sums[p].values += r.sums[p].values;
    }
  }
  for (std::size_t p = 0; p < sums.size(); ++p)
    EXPECT_NEAR(sums[p].finish().cbrt_cosine, by_gram.distances[p].cbrt_cosine,
                1e-9 * by_gram.distances[p].cbrt_cosine) << "pair " << p;
}

TEST_F(TinyDatabase, TheStudysFitsCanUseTheSparsePlacement) {
  // FitOptions::sparse (evaluate --sparse-inducing): every fit through the sparse likelihood,
  // whose value (a bound of the exact one) differs from the exact study's; the study still finds
  // the copy of material 2 by its projection. The sparse placement needs L-BFGS.
  StudyOptions o;
  o.dims = {2};
  o.layouts = {LayoutTransform{}};
  o.pairs = 2;
  o.block_columns = 1000;
  const StudyResult exact = run_layout_study(*set_, o);
  o.fit.sparse.inducing = 3;
  const StudyResult sparse = run_layout_study(*set_, o);
  const int n = static_cast<int>(set_->size());
  ASSERT_EQ(sparse.configs.size(), 1u);
  const ConfigResult& c = sparse.configs[0];
  EXPECT_EQ(c.latent.rows(), n);
  EXPECT_TRUE(c.latent.allFinite());
  EXPECT_NE(c.log_likelihood, exact.configs[0].log_likelihood);
  const LooEntry& copy = c.loo[static_cast<std::size_t>(n - 1)];
  EXPECT_LT(copy.gp.cbrt_cosine, 1e-3 * sparse.material_cbrt.maxCoeff());
  for (const LooEntry& e : c.loo) EXPECT_TRUE(std::isfinite(e.gp.cbrt_cosine));
  o.fit.optimize.method = gp::Optimizer::hooke_jeeves;
  EXPECT_THROW(run_layout_study(*set_, o), Error);
}

TEST_F(TinyDatabase, LeaveOneOutAgainstExplicitComputation) {
  StudyOptions o;
  o.dims = {2};
  o.layouts = {LayoutTransform{}};
  o.pairs = 4;
  o.path_segments = 4;
  o.block_columns = 1000;
  const StudyResult r = run_layout_study(*set_, o);
  const int n = static_cast<int>(set_->size());
  ASSERT_EQ(r.configs.size(), 1u);
  const ConfigResult& c = r.configs[0];
  ASSERT_EQ(c.loo.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(c.paths.size(), 4u);
  EXPECT_EQ(c.latent.rows(), n);

  // Material distances: symmetric and equal to the direct computation.
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      EXPECT_EQ(r.material_cbrt(i, j), r.material_cbrt(j, i));
      if (i < j) {
        EXPECT_NEAR(r.material_cbrt(i, j),
                    brdf_distance(tables_[static_cast<std::size_t>(i)], tables_[static_cast<std::size_t>(j)]).cbrt_cosine,
                    1e-10);
      }
    }

  // The copy: its nearest material is the original at distance 0, and the projection finds it.
  const int copy = n - 1;
  const LooEntry& e = c.loo[static_cast<std::size_t>(copy)];
  EXPECT_EQ(e.nearest_material, 2);
  EXPECT_EQ(e.nearest.cbrt_cosine, 0.0);
  EXPECT_LT(e.gp.cbrt_cosine, 1e-3 * r.material_cbrt.maxCoeff());

  // PCA entry of material 0 recomputed from the explicit tables.
  const std::size_t D = tables_[0].size();
  Eigen::MatrixXd Z(n - 1, static_cast<Eigen::Index>(D));
  for (int i = 1; i < n; ++i)
    for (int ch = 0; ch < 3; ++ch)
      for (std::size_t b = 0; b < tables_[0].bins(); ++b)
        Z(i - 1, static_cast<Eigen::Index>(ch * tables_[0].bins() + b)) = tables_[static_cast<std::size_t>(i)].value(ch, b);
  const Eigen::RowVectorXd mean = Z.colwise().mean();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Z.rowwise() - mean, Eigen::ComputeThinV);
  const Eigen::MatrixXd U = svd.matrixV().leftCols(2);
  Eigen::RowVectorXd z0(static_cast<Eigen::Index>(D));
  for (int ch = 0; ch < 3; ++ch)
    for (std::size_t b = 0; b < tables_[0].bins(); ++b)
      z0(static_cast<Eigen::Index>(ch * tables_[0].bins() + b)) = tables_[0].value(ch, b);
  const Eigen::RowVectorXd rec = mean + ((z0 - mean) * U) * U.transpose();
  BrdfTable pca(kTiny);
  for (int ch = 0; ch < 3; ++ch)
    for (std::size_t b = 0; b < pca.bins(); ++b)
      pca.set_value(ch, b, rec(static_cast<Eigen::Index>(ch * pca.bins() + b)));
  // set_value divides by the channel scale and value() multiplies back: compare with tolerance.
  const BrdfDistance expected = brdf_distance(pca, tables_[0]);
  EXPECT_NEAR(c.loo[0].pca.cosine_rmse, expected.cosine_rmse, 1e-8 * (1 + expected.cosine_rmse));
  EXPECT_NEAR(c.loo[0].pca.cbrt_cosine, expected.cbrt_cosine, 1e-6 * (1 + expected.cbrt_cosine));

  // Paths: steps obey the triangle inequality against the ends.
  for (const PathEntry& p : c.paths) {
    ASSERT_EQ(p.steps.size(), 4u);
    double length = 0;
    for (const auto& s : p.steps) length += s.cbrt_cosine;
    EXPECT_GE(length, p.ends.cbrt_cosine * (1 - 1e-9));
  }
  EXPECT_GE(c.path_length_ratio, 1.0 - 1e-9);
  EXPECT_FALSE(r.recommendation.empty());
}

TEST_F(TinyDatabase, MaterialsOptionLimitsTheLeftOutSet) {
  StudyOptions o;
  o.dims = {1, 2};
  o.layouts = {LayoutTransform::parse("cbrt"), LayoutTransform::parse("cosine-linear")};
  o.materials = 3;
  o.pairs = 0;
  const StudyResult r = run_layout_study(*set_, o);
  ASSERT_EQ(r.configs.size(), 4u);
  for (const auto& c : r.configs) {
    EXPECT_EQ(c.loo.size(), 3u);
    EXPECT_TRUE(c.paths.empty());
    EXPECT_GE(c.loo_pca_cbrt, 0.0);
  }
  EXPECT_NO_THROW(r.config(LayoutTransform::parse("cbrt"), 2));
  EXPECT_THROW(r.config(LayoutTransform::parse("log"), 2), Error);
}

TEST(AutomaticStride, KeepsThePassWithinItsBudget) {
  EXPECT_EQ(automatic_stride(10, 1000, 1e9), 1);     // within the budget: every value
  EXPECT_EQ(automatic_stride(1000, 1000, 1e6), 1);   // exactly at it
  EXPECT_EQ(automatic_stride(1001, 1000, 1e6), 2);   // just over: every second value
  // The default run on 8 MERL-size tables (6472 tables in the pass): every 29th value.
  EXPECT_EQ(automatic_stride(6472, 3 * 90 * 90 * 180, 1e9), 29);
  EXPECT_EQ(automatic_stride(5, 100, 0.0), 1);        // no budget: every value
}

TEST(AutomaticHeldOut, ShrinksPastFiftyMaterials) {
  EXPECT_EQ(automatic_held_out(8), 8);      // every material of a small database
  EXPECT_EQ(automatic_held_out(24), 24);
  EXPECT_EQ(automatic_held_out(50), 24);
  EXPECT_EQ(automatic_held_out(83), 14);    // 1200 / 83
  EXPECT_EQ(automatic_held_out(100), 12);
  EXPECT_EQ(automatic_held_out(150), 8);
  EXPECT_EQ(automatic_held_out(1000), 8);   // never fewer than 8
}

TEST_F(TinyDatabase, TheDefaultStrideFollowsTheBudgetAndIsReported) {
  StudyOptions o;
  o.dims = {2};
  o.layouts = {LayoutTransform{}};
  o.pairs = 2;
  o.path_segments = 2;
  const StudyResult all = run_layout_study(*set_, o);  // a tiny database: within the budget
  EXPECT_EQ(all.value_stride, 1);
  o.compared_values_budget = 1000.0;  // force a stride
  const StudyResult some = run_layout_study(*set_, o);
  EXPECT_GT(some.value_stride, 1);
  // Each distance then compares about 1/stride of the values.
  EXPECT_NEAR(static_cast<double>(some.compared_values),
              static_cast<double>(all.compared_values) / some.value_stride, 1.0 + all.compared_values * 0.01);
  o.value_stride = 3;  // an explicit stride wins
  EXPECT_EQ(run_layout_study(*set_, o).value_stride, 3);
}

TEST(ChoosePairs, DistinctDeterministicAndLimited) {
  const auto a = choose_pairs(10, 7, 3), b = choose_pairs(10, 7, 3);
  EXPECT_EQ(a, b);
  ASSERT_EQ(a.size(), 7u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_LT(a[k].first, a[k].second);
    if (k) {
      EXPECT_NE(a[k], a[k - 1]);
    }
  }
  EXPECT_EQ(choose_pairs(4, 100, 1).size(), 6u);
}

}  // namespace
}  // namespace matlas::eval
