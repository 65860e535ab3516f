// matlas sample-plan and fit-samples end to end: a plan filled in with an input's values fits back
// to that input's table; bad sample files are refused naming the file and the line.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/in_process.h"
#include "core/atomic_file.h"
#include "formats/sample_file.h"
#include "manifold/synthetic_database.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

class CliAcquisition : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-cli-acquisition");
    paths_ = test::write_database(dir_->path() / "db", 10, 8);
    const auto r = test::call_matlas({"build", (dir_->path() / "db").string(), "-o", model(), "--dim", "2", "--quiet"});
    ASSERT_EQ(r.code, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string model() { return (dir_->path() / "m.matlas").string(); }
  /// The plan's rows filled in with the values of table `t`.
  static std::string filled(const std::string& plan_csv, const BrdfTable& t) {
    std::vector<MeasuredSample> rows = parse_samples(plan_csv, "plan").samples;
    for (auto& s : rows) {
      const std::size_t bin = bin_of(t.dims(), s.wi, s.wo);
      for (int c = 0; c < 3; ++c) s.value[c] = t.value(c, bin);
      s.measured = true;
    }
    return format_samples_csv(rows);
  }
  static inline test::TempDir* dir_ = nullptr;
  static inline std::vector<fs::path> paths_;
};

TEST_F(CliAcquisition, APlanFilledWithAnInputsValuesFitsBackToThatInput) {
  const test::TempDir out("matlas-cli-acquisition-out");
  const auto plan = test::call_matlas({"sample-plan", model(), "-k", "8", "-o", (out / "plan.csv").string()});
  ASSERT_EQ(plan.code, 0) << plan.err;
  EXPECT_HAS(plan.out, "8 directions");
  const std::string plan_csv = read_file(out / "plan.csv");
  EXPECT_EQ(plan_csv.rfind("# matlas sample-plan: 8 directions", 0), 0u) << plan_csv;
  const SampleFile planned = parse_samples(plan_csv, "plan.csv");
  ASSERT_EQ(planned.samples.size(), 8u);
  for (const auto& s : planned.samples) EXPECT_FALSE(s.measured);

  const BrdfTable truth = read_merl(paths_[3]);
  write_file_atomic(out / "measured.csv", filled(plan_csv, truth));
  // (The test grid is small, so no -o: MERL files for other tools are 90 x 90 x 180 only.)
  const auto fit = test::call_matlas({"fit-samples", model(), (out / "measured.csv").string(), "--report",
                                      (out / "fit.json").string()});
  ASSERT_EQ(fit.code, 0) << fit.err;
  EXPECT_HAS(fit.out, "best single input mat03");
  const auto report = nlohmann::json::parse(read_file(out / "fit.json"));
  EXPECT_EQ(report["best_input"], "mat03");
  ASSERT_GE(report["weights"].size(), 1u);
  EXPECT_EQ(report["weights"][0]["name"], "mat03");  // largest first
  EXPECT_GT(report["weights"][0]["weight"].get<double>(), 0.99);
  EXPECT_EQ(report["samples"].size(), 8u);
  EXPECT_EQ(report["x"].size(), 2u);
  EXPECT_EQ(report["latent_covariance"].size(), 2u);

  // --simulate fills the plan with a table's values: the same file as filled by hand.
  const auto simulated = test::call_matlas({"sample-plan", model(), "-k", "8", "--simulate", paths_[3].string(), "-o",
                                            (out / "simulated.csv").string()});
  ASSERT_EQ(simulated.code, 0) << simulated.err;
  const SampleFile sim = parse_samples(read_file(out / "simulated.csv"), "simulated.csv");
  const SampleFile by_hand = parse_samples(read_file(out / "measured.csv"), "measured.csv");
  ASSERT_EQ(sim.samples.size(), by_hand.samples.size());
  for (std::size_t k = 0; k < sim.samples.size(); ++k) {
    EXPECT_TRUE(sim.samples[k].measured);
    EXPECT_LT((sim.samples[k].value - by_hand.samples[k].value).abs().maxCoeff(), 1e-6);
  }

  // The next directions given those measurements are new ones.
  const auto next = test::call_matlas({"sample-plan", model(), "-k", "2", "--given", (out / "measured.csv").string(), "-o",
                                       (out / "next.csv").string()});
  ASSERT_EQ(next.code, 0) << next.err;
  EXPECT_HAS(next.out, "given 8 measured samples");
  for (const auto& s : parse_samples(read_file(out / "next.csv"), "next.csv").samples)
    for (const auto& p : planned.samples) EXPECT_GT((s.wi - p.wi).norm() + (s.wo - p.wo).norm(), 1e-6);
}

TEST_F(CliAcquisition, BadSampleFilesAreRefusedNamingTheFileAndTheLine) {
  const test::TempDir out("matlas-cli-acquisition-bad");
  const fs::path bad = out / "bad.csv";
  write_file_atomic(bad, "theta_i,phi_i,theta_o,phi_o,r,g,b\n10,0,20,180,0.1,0.1,0.1\n95,0,20,180,0.1,0.1,0.1\n"
                         "10,0,30,180,0.1,0.1,0.1\n20,0,30,180,0.1,0.1,0.1\n");
  const auto r = test::call_matlas({"fit-samples", model(), bad.string(), "-o", (out / "x.binary").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_HAS(r.err, bad.string());
  EXPECT_HAS(r.err, "line 3: theta_i = 95 is at or below the horizon");
  EXPECT_FALSE(fs::exists(out / "x.binary"));
  // Skipped, the three good samples are enough for q = 2 and the skip is reported.
  const auto skipped = test::call_matlas({"fit-samples", model(), bad.string(), "--skip-invalid", "--json"});
  EXPECT_EQ(skipped.code, 0) << skipped.err;
  EXPECT_EQ(nlohmann::json::parse(skipped.out)["skipped"].size(), 1u);
  // Too few samples for the map say so.
  const fs::path two = out / "two.csv";
  write_file_atomic(two, "theta_i,phi_i,theta_o,phi_o,r,g,b\n10,0,20,180,0.1,0.1,0.1\n10,0,30,180,0.1,0.1,0.1\n");
  const auto few = test::call_matlas({"fit-samples", model(), two.string(), "--json"});
  EXPECT_EQ(few.code, 1);
  EXPECT_HAS(few.err, "2 measured samples cannot place a point on a map of dimension 2");
  const auto nothing = test::call_matlas({"fit-samples", model(), two.string()});
  EXPECT_EQ(nothing.code, 1);
  EXPECT_HAS(nothing.err, "nothing to write");
}

}  // namespace
}  // namespace matlas
