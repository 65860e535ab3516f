// POST /api/fit-samples and /api/sample-plan end to end (issue 30): samples of a database material
// land on its latent point, invalid rows are reported by line, bad files get a 400 with the
// parser's message, and a plan is k distinct directions in the sample file's CSV.
#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "brdf/merl_grid.h"
#include "formats/merl_file.h"
#include "formats/sample_file.h"
#include "server/atlas_server.h"
#include "support/temp_dir.h"
#include "small_model.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

using nlohmann::json;

class AcquisitionEndpoints : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-server-acquisition");
    model_ = new Model(test::build_small_model(dir_->path(), 6, 17));
    previews_ = test::sphere_previews(*model_, 16, 1);
    ServerOptions so;
    so.port = 0;
    so.threads = 8;
    server_ = new AtlasServer(*model_, previews_, so);
    server_->start();
  }
  static void TearDownTestSuite() {
    delete server_;
    previews_.reset();
    delete model_;
    delete dir_;
  }
  static httplib::Client client() {
    httplib::Client c("127.0.0.1", server_->port());
    c.set_read_timeout(60, 0);
    return c;
  }
  /// `count` samples of database material `index` at random directions above 80 degrees.
  static std::vector<MeasuredSample> samples_of(int index, int count, unsigned seed) {
    const BrdfTable table = read_merl(dir_->path() / "db" / (model_->names()[static_cast<std::size_t>(index)] + ".binary"));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto direction = [&] {
      const double z = 0.18 + 0.82 * u(rng), phi = 6.283185307179586 * u(rng), s = std::sqrt(1 - z * z);
      return Vec3(s * std::cos(phi), s * std::sin(phi), z);
    };
    std::vector<MeasuredSample> out;
    while (static_cast<int>(out.size()) < count) {
      MeasuredSample s;
      s.wi = direction();
      s.wo = direction();
      const std::size_t bin = bin_of(table.dims(), s.wi, s.wo);
      const std::size_t bins = table.bins();
      if (!model_->kept(bin) || !model_->kept(bins + bin) || !model_->kept(2 * bins + bin)) continue;
      for (int c = 0; c < 3; ++c) s.value[c] = table.value(c, bin);
      s.measured = true;
      out.push_back(s);
    }
    return out;
  }
  static json expect_ok(const httplib::Result& r) {
    EXPECT_TRUE(r);
    if (!r) return json();
    EXPECT_EQ(r->status, 200) << r->body;
    return json::parse(r->body, nullptr, false);
  }
  static std::string expect_error(const httplib::Result& r, int status) {
    EXPECT_TRUE(r);
    if (!r) return "";
    EXPECT_EQ(r->status, status) << r->body;
    const json j = json::parse(r->body, nullptr, false);
    EXPECT_TRUE(j.is_object() && j.contains("error")) << r->body;
    return j.is_object() && j.contains("error") ? j["error"].get<std::string>() : "";
  }

  static inline test::TempDir* dir_ = nullptr;
  static inline Model* model_ = nullptr;
  static inline std::shared_ptr<BasisPreviews> previews_;
  static inline AtlasServer* server_ = nullptr;
};

TEST_F(AcquisitionEndpoints, SamplesOfAMaterialLandOnItsLatentPoint) {
  const std::string csv = format_samples_csv(samples_of(3, 30, 5), {"material 3"});
  const json j = expect_ok(client().Post("/api/fit-samples", csv, "text/csv"));
  ASSERT_TRUE(j.is_object());
  const Eigen::VectorXd extent = model_->latent_max() - model_->latent_min();
  for (int d = 0; d < 2; ++d) EXPECT_NEAR(j["x"][d].get<double>(), model_->latent()(3, d), 0.02 * extent[d]) << j.dump();
  EXPECT_EQ(j["best_input"]["index"], 3);
  EXPECT_EQ(j["best_input"]["name"], model_->names()[3]);
  EXPECT_EQ(j["used"], 30);
  ASSERT_EQ(j["samples"].size(), 30u);
  EXPECT_EQ(j["samples"][0]["line"], 3);  // one comment line and the header before it
  EXPECT_LT(j["rms_residual"].get<double>(), 1e-3);
  EXPECT_EQ(j["weights"][0]["index"], 3);
  EXPECT_TRUE(j["combined"].is_boolean());
  ASSERT_EQ(j["covariance"].size(), 2u);
  ASSERT_EQ(j["covariance"][0].size(), 2u);
  ASSERT_EQ(j["latent_sigma"].size(), 2u);
  EXPECT_TRUE(j["skipped"].empty());

  // The same samples as JSON; and one corrupted (10 times too bright) is flagged, the point stays.
  std::vector<MeasuredSample> samples = samples_of(3, 30, 5);
  samples[7].value *= 10.0;
  json doc = {{"samples", json::array()}};
  for (const auto& s : samples)
    doc["samples"].push_back({{"wi", {s.wi.x(), s.wi.y(), s.wi.z()}}, {"wo", {s.wo.x(), s.wo.y(), s.wo.z()}},
                              {"rgb", {s.value[0], s.value[1], s.value[2]}}});
  const json k = expect_ok(client().Post("/api/fit-samples", doc.dump(), "application/json"));
  ASSERT_TRUE(k.is_object());
  for (int d = 0; d < 2; ++d) EXPECT_NEAR(k["x"][d].get<double>(), model_->latent()(3, d), 0.02 * extent[d]) << k.dump();
  EXPECT_EQ(k["outliers"], 1);
  EXPECT_TRUE(k["samples"][7]["outlier"].get<bool>());
  EXPECT_EQ(k["samples"][7]["line"], 8);  // "sample 8"
  EXPECT_FALSE(k["samples"][6]["outlier"].get<bool>());
}

TEST_F(AcquisitionEndpoints, InvalidRowsAreSkippedAndReportedByLine) {
  std::string csv = format_samples_csv(samples_of(1, 12, 9));
  csv += "95,0,30,180,brdf,0.1,0.1,0.1,,,\n";  // line 14: below the horizon
  const json j = expect_ok(client().Post("/api/fit-samples", csv, "text/csv"));
  ASSERT_TRUE(j.is_object());
  ASSERT_EQ(j["skipped"].size(), 1u) << j.dump();
  EXPECT_NE(j["skipped"][0].get<std::string>().find("line 14"), std::string::npos) << j["skipped"][0];
  EXPECT_EQ(j["used"], 12);
}

TEST_F(AcquisitionEndpoints, BadFilesGet4xxWithTheParsersMessage) {
  EXPECT_NE(expect_error(client().Post("/api/fit-samples", "", "text/csv"), 400).find("empty"), std::string::npos);
  EXPECT_NE(expect_error(client().Post("/api/fit-samples", "a,b,c\n1,2,3\n", "text/csv"), 400).find("upload"),
            std::string::npos);
  EXPECT_NE(expect_error(client().Post("/api/fit-samples", "theta_i,phi_i,theta_o,phi_o,r,g,b\n10,0,x,0,1,1,1\n", "text/csv"), 400)
                .find("line 2"),
            std::string::npos);
  // Every row invalid: nothing to fit, and the first reason is given.
  EXPECT_NE(expect_error(client().Post("/api/fit-samples", "theta_i,phi_i,theta_o,phi_o,r,g,b\n95,0,10,0,1,1,1\n", "text/csv"), 400)
                .find("line 2"),
            std::string::npos);
  expect_error(client().Post("/api/fit-samples", "{\"samples\": [", "application/json"), 400);
  expect_error(client().Post("/api/fit-samples", std::string(100000, '[') + std::string(100000, ']'), "application/json"), 400);
  // Too few samples for q = 2: 422 saying so.
  const std::string two = format_samples_csv(samples_of(2, 2, 3));
  expect_error(client().Post("/api/fit-samples", two, "text/csv"), 422);
  expect_error(client().Post("/api/fit-samples?robust=maybe", format_samples_csv(samples_of(2, 5, 3)), "text/csv"), 400);
  expect_error(client().Post("/api/fit-samples", std::string(2u << 20, '1'), "text/csv"), 413);
  expect_error(client().Post("/api/sample-plan?k=0", "", "text/csv"), 400);
  expect_error(client().Post("/api/sample-plan?k=abc", "", "text/csv"), 400);
  expect_error(client().Post("/api/sample-plan", "not a sample file", "text/csv"), 400);
  auto alive = client().Get("/api/model");
  ASSERT_TRUE(alive);
  EXPECT_EQ(alive->status, 200);
}

TEST_F(AcquisitionEndpoints, APlanIsKDistinctDirectionsAndItsCsvReadsBack) {
  const json j = expect_ok(client().Post("/api/sample-plan?k=6", "", "text/csv"));
  ASSERT_TRUE(j.is_object());
  ASSERT_EQ(j["directions"].size(), 6u);
  EXPECT_EQ(j["conditioned_on"], 0);
  std::set<std::size_t> bins;
  for (const auto& d : j["directions"]) {
    const Vec3 wi(d["wi"][0].get<double>(), d["wi"][1].get<double>(), d["wi"][2].get<double>());
    const Vec3 wo(d["wo"][0].get<double>(), d["wo"][1].get<double>(), d["wo"][2].get<double>());
    EXPECT_GT(wi.z(), 0);
    EXPECT_GT(wo.z(), 0);
    EXPECT_LT(d["theta_i"].get<double>(), 90);
    bins.insert(bin_of(model_->dims(), wi, wo));
  }
  EXPECT_EQ(bins.size(), 6u);
  const SampleFile plan = parse_samples(j["csv"].get<std::string>(), "plan");
  ASSERT_EQ(plan.samples.size(), 6u);
  EXPECT_TRUE(plan.measured().empty());

  // Sequential: given samples, the next direction is none of theirs.
  const std::vector<MeasuredSample> have = samples_of(4, 8, 21);
  const json next = expect_ok(client().Post("/api/sample-plan?k=1", format_samples_csv(have), "text/csv"));
  ASSERT_TRUE(next.is_object());
  EXPECT_EQ(next["conditioned_on"], 8);
  ASSERT_EQ(next["directions"].size(), 1u);
}

}  // namespace
}  // namespace matlas::server
