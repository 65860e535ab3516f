// The sparse-reconstruction study (matlas evaluate --sparse) on a tiny synthetic database: every
// method and K is reported for every left-out material, the robustness test may use more samples
// than any K, runs are reproducible, and bad options are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "brdf/catalog.h"
#include "core/error.h"
#include "eval/sparse_study.h"
#include "formats/synth_database.h"
#include "manifold/material_set.h"
#include "support/temp_dir.h"

namespace matlas::eval {
namespace {

class SparseStudyTest : public ::testing::Test {
protected:
  void SetUp() override {
    write_database(dir_.path(), random_catalog(7, 11), null_progress(), MerlDims{10, 10, 20});
    set_ = std::make_unique<MaterialSet>(MaterialSet::open({dir_.path()}));
  }
  static SparseStudyOptions small_options() {
    SparseStudyOptions o;
    o.counts = {4, 8};
    o.robustness_count = 12;  // more than every K: the plan must serve it too
    o.candidates = 300;
    o.evaluation_values = 5000;
    o.materials = 2;
    o.pca_ridges = {1e-3, 1e-1};
    o.pca_condition_components = 4;
    return o;
  }
  test::TempDir dir_{"matlas-sparse-study"};
  std::unique_ptr<MaterialSet> set_;
};

TEST_F(SparseStudyTest, ReportsEveryMethodAndCountForEveryLeftOutMaterial) {
  const SparseStudyOptions o = small_options();
  const SparseStudy study = run_sparse_study(*set_, o, null_progress());
  ASSERT_EQ(study.materials.size(), 2u);
  EXPECT_EQ(study.inputs, 6);
  for (const char* method : {"matlas-planned", "matlas-random", "pca-condition", "pca-random"})
    for (int k : o.counts) {
      const SparseResult& r = study.find(method, k);
      ASSERT_EQ(r.error.size(), 2u) << method << " K=" << k;
      for (double e : r.error) EXPECT_TRUE(std::isfinite(e) && e >= 0) << method << " K=" << k << ": " << e;
      EXPECT_NEAR(r.mean, (r.error[0] + r.error[1]) / 2, 1e-12);
    }
  EXPECT_EQ(study.robustness_count, 12);
  EXPECT_TRUE(std::isfinite(study.clean) && std::isfinite(study.corrupted) && std::isfinite(study.corrupted_least_squares));
  // The nearest input is some other material: a positive distance for distinct random materials.
  EXPECT_GT(study.nearest_input, 0.0);
  // Seeded and deterministic (the materials are studied in parallel).
  const SparseStudy again = run_sparse_study(*set_, o, null_progress());
  for (const SparseResult& r : study.results) EXPECT_EQ(again.find(r.method, r.count).error, r.error) << r.method;
  EXPECT_EQ(again.clean, study.clean);
}

TEST_F(SparseStudyTest, RefusesCountsItCannotServe) {
  SparseStudyOptions o = small_options();
  o.counts = {2};  // below q + 1 = 3
  EXPECT_THROW(run_sparse_study(*set_, o, null_progress()), Error);
  o = small_options();
  o.robustness_count = 100000;  // more than the candidate directions
  EXPECT_THROW(run_sparse_study(*set_, o, null_progress()), Error);
  o = small_options();
  o.outlier_share = 0.9;
  EXPECT_THROW(run_sparse_study(*set_, o, null_progress()), Error);
}

}  // namespace
}  // namespace matlas::eval
