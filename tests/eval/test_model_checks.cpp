// Checks of a built model (items 1-4) on a tiny synthetic database, and the report files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdf/catalog.h"
#include "core/atomic_file.h"
#include "eval/manifold_quality.h"
#include "eval/model_checks.h"
#include "eval/report.h"
#include "formats/merl_file.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/export.h"
#include "support/temp_dir.h"

namespace matlas::eval {
namespace {

class TinyModel : public ::testing::Test {
protected:
  void SetUp() override {
    write_database(dir_ / "db", random_catalog(6, 11), null_progress(), MerlDims{6, 6, 12});
    set_ = std::make_unique<MaterialSet>(MaterialSet::open({dir_ / "db"}));
    BuildOptions o;
    o.dim = 2;
    o.block_columns = 500;
    build_model(*set_, o, dir_ / "m.matlas");
    model_ = std::make_unique<Model>(Model::open(dir_ / "m.matlas"));
  }
  test::TempDir dir_{"matlas-eval-model"};
  std::unique_ptr<MaterialSet> set_;
  std::unique_ptr<Model> model_;
};

TEST_F(TinyModel, ChecksHoldOnAGoodModel) {
  ModelCheckOptions o;
  o.reciprocity_pairs = 300;
  o.sample_points = 4;
  o.map_resolution = 6;
  const ModelChecks c = run_model_checks(*model_, set_.get(), o);
  ASSERT_TRUE(c.interpolation.available);
  ASSERT_EQ(c.interpolation.max_relative_error.size(), 6u);
  // float32 storage of mean and centred data: rounding relative to the largest value of a column.
  double peak = 0;
  for (std::size_t i = 0; i < set_->size(); ++i) {
    const BrdfTable t = read_merl(set_->file(i).path());
    for (int ch = 0; ch < 3; ++ch)
      for (std::size_t b = 0; b < t.bins(); ++b) peak = std::max(peak, t.value(ch, b));
  }
  for (double e : c.interpolation.max_abs_error) EXPECT_LT(e, 1e-6 * peak);  // float32 storage
  EXPECT_LT(c.interpolation.max_weight_error, 1e-8);
  EXPECT_EQ(c.interpolation.column_mismatches, 0u);
  EXPECT_EQ(c.reciprocity.pairs, 4 * 300);
  EXPECT_LT(c.reciprocity.max_relative_difference, 1e-12);
  EXPECT_LT(c.albedo.max_relative_error, 1e-6);        // albedo is linear in the table
  EXPECT_LT(c.albedo.max_relative_error_model, 1e-3);  // stored curves: same quadrature, float data
  EXPECT_GE(c.albedo.max_relative_error_clamped, c.albedo.max_relative_error * 0.5);
  ASSERT_EQ(c.map.negative_fraction.size(), 36u);
  for (double f : c.map.negative_fraction) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
  }
  EXPECT_GT(c.map.worst_max_albedo, 0.0);
}

TEST_F(TinyModel, ASpreadOfMaterialsIsCheckedAndAChangedTableIsFound) {
  // Item 1 on 3 of the 6 materials (0, 2 and 4, evenly spread), after material 2's file changed
  // by a known amount at one kept value: that material's error is the change, the others' the
  // float32 storage's; with 0 (all), every material in order.
  const std::size_t bin = model_->dims().bins() / 2;
  ASSERT_TRUE(model_->kept(bin)) << "the test changes a value the model keeps (red channel)";
  const std::filesystem::path file = set_->file(2).path();
  BrdfTable t = read_merl(file);
  double peak = 0;  // of every table: the float32 storage rounds at ~6e-8 of it
  for (std::size_t i = 0; i < set_->size(); ++i) {
    const BrdfTable u = read_merl(set_->file(i).path());
    for (int ch = 0; ch < 3; ++ch)
      for (std::size_t b = 0; b < u.bins(); ++b) peak = std::max(peak, u.value(ch, b));
  }
  const double change = 0.5 * peak;
  t.set_value(0, bin, t.value(0, bin) + change);
  write_merl(file, t, true);
  const MaterialSet changed = MaterialSet::open({dir_ / "db"});
  ModelCheckOptions o;
  o.reciprocity_pairs = 10;
  o.sample_points = 2;
  o.map_resolution = 4;
  o.interpolation_materials = 3;
  const InterpolationCheck some = run_model_checks(*model_, &changed, o).interpolation;
  ASSERT_TRUE(some.available);
  EXPECT_EQ(some.materials, (std::vector<int>{0, 2, 4}));
  ASSERT_EQ(some.max_abs_error.size(), 3u);
  EXPECT_NEAR(some.max_abs_error[1], change, 1e-6 * change);  // material 2
  EXPECT_LT(some.max_abs_error[0], 1e-6 * peak);
  EXPECT_LT(some.max_abs_error[2], 1e-6 * peak);
  EXPECT_EQ(some.column_mismatches, 0u);
  o.interpolation_materials = 0;
  const InterpolationCheck all = run_model_checks(*model_, &changed, o).interpolation;
  EXPECT_EQ(all.materials, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(all.max_abs_error[static_cast<std::size_t>(2 * k)], some.max_abs_error[static_cast<std::size_t>(k)],
                1e-12 * change) << "material " << 2 * k;
}

TEST_F(TinyModel, AFloat16ModelIsCheckedAtItsOwnRounding) {
  // Item 1 reads float16 storage too: each value within half-precision rounding (2^-11 of
  // itself) of the file's, so the error relative to each material's peak is between float32's
  // and 2^-11.
  BuildOptions o;
  o.dim = 2;
  o.storage = Storage::f16;
  build_model(*set_, o, dir_ / "h.matlas");
  const Model half = Model::open(dir_ / "h.matlas");
  ModelCheckOptions co;
  co.reciprocity_pairs = 10;
  co.sample_points = 2;
  co.map_resolution = 4;
  const InterpolationCheck c = run_model_checks(half, set_.get(), co).interpolation;
  ASSERT_TRUE(c.available);
  ASSERT_EQ(c.max_relative_error.size(), 6u);
  for (double e : c.max_relative_error) {
    EXPECT_LE(e, std::ldexp(1.0, -11) * 1.01);
    EXPECT_GT(e, 1e-6);
  }
  EXPECT_EQ(c.column_mismatches, 0u);
}

TEST_F(TinyModel, NegativeCountsMatchTheExportClamp) {
  // Far outside the data the GP extrapolates to the mean; between far-apart points it can
  // overshoot. Whatever the count, it must be what export_table clamps.
  const int n = model_->count();
  Eigen::MatrixXd W(n, 3);
  W.col(0) = model_->material_weights(0);
  W.col(1) = Eigen::VectorXd::Constant(n, 0.0);
  W(0, 1) = 3.0, W(1, 1) = -2.0;  // strong extrapolation: surely some negative values
  W.col(2) = model_->weights(0.5 * (model_->latent().row(0) + model_->latent().row(1)).transpose());
  const std::vector<std::size_t> neg = count_negative_values(*model_, W);
  EXPECT_EQ(neg[0], 0u);
  EXPECT_GT(neg[1], 0u);
  for (int k = 0; k < 3; ++k) {
    ExportStats s;
    const BrdfTable t = export_table(*model_, W.col(k), &s);
    EXPECT_EQ(s.clamped, neg[static_cast<std::size_t>(k)]) << k;
    for (int ch = 0; ch < 3; ++ch)
      for (std::size_t b = 0; b < t.bins(); ++b)
        if (model_->kept(ch * t.bins() + b)) {
          EXPECT_GE(t.value(ch, b), 0.0);
        }
  }
}

TEST_F(TinyModel, StridedNegativeCountsLookAtEveryStrideThValue) {
  const int n = model_->count();
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(n, 2);
  W(0, 0) = 3.0, W(1, 0) = -2.0;  // extrapolation: negative values
  W(2, 1) = 2.5, W(3, 1) = -1.5;
  const std::size_t values = 3 * model_->dims().bins();
  for (const std::size_t stride : {1u, 3u, 7u}) {
    std::size_t visited = 0;
    const std::vector<std::size_t> neg = count_negative_values(*model_, W, stride, &visited);
    std::size_t kept = 0;
    for (int k = 0; k < 2; ++k) {
      std::size_t expected = 0;
      for (std::size_t v = 0; v < values; v += stride)
        if (model_->kept(v)) expected += model_->value(v, W.col(k)) < 0.0 ? 1 : 0;
      EXPECT_EQ(neg[static_cast<std::size_t>(k)], expected) << "stride " << stride << ", point " << k;
    }
    for (std::size_t v = 0; v < values; v += stride) kept += model_->kept(v) ? 1 : 0;
    EXPECT_EQ(visited, kept) << "stride " << stride;
    EXPECT_GT(neg[0], 0u);
  }
  // The inputs' own counts, read directly, are the identity's.
  const std::vector<std::size_t> inputs = count_negative_inputs(*model_);
  EXPECT_EQ(inputs, count_negative_values(*model_, Eigen::MatrixXd::Identity(n, n)));
  // What lets the checks skip a count: a convex mix of inputs without negatives has none.
  ASSERT_EQ(inputs, std::vector<std::size_t>(static_cast<std::size_t>(n), 0));
  const Eigen::VectorXd mix = Eigen::VectorXd::Constant(n, 1.0 / n);
  EXPECT_TRUE(non_negative_by_construction(mix, inputs));
  EXPECT_EQ(count_negative_values(*model_, mix)[0], 0u);
  EXPECT_FALSE(non_negative_by_construction(W.col(0), inputs));   // a negative weight
  EXPECT_FALSE(non_negative_by_construction(0.5 * mix, inputs));  // not summing to 1
  std::vector<std::size_t> one_negative = inputs;
  one_negative[0] = 1;
  EXPECT_FALSE(non_negative_by_construction(mix, one_negative));
}

TEST_F(TinyModel, ManifoldQualityCountsWithinItsBudget) {
  // The default counts every value at this size; a small budget strides the GP's counts (the
  // convex mode's points mix non-negative inputs: none to count), and at most `midpoints`
  // materials' pairs are looked at.
  ASSERT_EQ(count_negative_inputs(*model_), std::vector<std::size_t>(6, 0));
  ManifoldQualityOptions o;
  o.hull_points = 20;
  const ManifoldQuality full = assess_manifold(*model_, o);
  ASSERT_EQ(full.plausibility.size(), 4u);
  for (const ModePlausibility& p : full.plausibility) {
    EXPECT_EQ(p.value_stride, 1) << p.mode << " " << p.where;
    EXPECT_EQ(p.points, p.where == std::string("hull") ? 20 : 6) << p.mode << " " << p.where;
    if (p.mode == "convex") {
      EXPECT_EQ(p.with_negative, 0);
    }
  }
  o.midpoints = 3;
  o.negative_budget = 1e4;
  const ManifoldQuality strided = assess_manifold(*model_, o);
  const double values = 3.0 * static_cast<double>(model_->dims().bins());
  for (const ModePlausibility& p : strided.plausibility) {
    EXPECT_EQ(p.points, p.where == std::string("hull") ? 20 : 3) << p.mode << " " << p.where;
    if (p.mode == "gp") {
      EXPECT_EQ(p.value_stride, static_cast<int>(std::ceil(p.points * 6 * values / 1e4))) << p.where;
    } else {
      EXPECT_EQ(p.value_stride, 1) << "no convex point needs a count: " << p.where;
    }
  }
}

TEST_F(TinyModel, ReportIsWrittenAndSelfContained) {
  ModelCheckOptions o;
  o.reciprocity_pairs = 50;
  o.sample_points = 2;
  o.map_resolution = 4;
  const ModelChecks c = run_model_checks(*model_, set_.get(), o);
  StudyOptions so;
  so.dims = {2};
  so.layouts = {LayoutTransform{}};
  so.pairs = 2;
  so.path_segments = 3;
  const StudyResult s = run_layout_study(*set_, so);
  ReportInput ri;
  ri.command = "test";
  ri.input = "tiny";
  ri.study = &s;
  ri.checks = &c;
  write_report(dir_ / "report", ri);
  for (const char* f : {"index.html", "report.json", "loo.csv", "configs.csv", "paths.csv", "map.csv",
                        "material_distances.csv", "interpolation.csv", "map_negative.png", "map_albedo.png"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir_ / "report" / f)) << f;
  const std::string html = read_file(dir_ / "report" / "index.html");
  EXPECT_EQ(html.find("/*MATLAS_DATA*/"), std::string::npos);
  EXPECT_EQ(html.find("/*MATLAS_CHARTJS*/"), std::string::npos);
  EXPECT_EQ(html.find("<script src="), std::string::npos);  // nothing loaded from outside
  const nlohmann::json j = nlohmann::json::parse(read_file(dir_ / "report" / "report.json"));
  EXPECT_EQ(j["study"]["configs"].size(), 1u);
  EXPECT_EQ(j["study"]["configs"][0]["loo"].size(), 6u);
  EXPECT_EQ(j["model_checks"]["map"]["negative_fraction"].size(), 16u);
  const std::string loo = read_file(dir_ / "report" / "loo.csv");
  EXPECT_EQ(std::count(loo.begin(), loo.end(), '\n'), 7);
}

}  // namespace
}  // namespace matlas::eval
