// Sample files: CSV and JSON, angles and vectors, BRDF values and radiance ratios, uncertainties,
// invalid rows reported by line, and the plan's CSV read back.
#include <cmath>

#include <gtest/gtest.h>

#include "formats/sample_file.h"
#include "support/error_of.h"

namespace matlas {
namespace {

using test::error_of;

TEST(SampleFile, ReadsAnglesValuesAndUncertaintiesFromCsv) {
  const SampleFile f = parse_samples(
      "# a comment\n"
      "Theta_i, phi_i ,theta_o,phi_o,r,g,b,sigma_r,sigma_g,sigma_b,note\n"
      "\n"
      "30,0,45,180,0.5,0.25,0.125,0.01,0.02,0.03,first\r\n"
      "0,0,60,90,1,2,3,,,,\n",
      "s.csv");
  ASSERT_EQ(f.samples.size(), 2u);
  const MeasuredSample& a = f.samples[0];
  EXPECT_EQ(a.line, 4);
  EXPECT_TRUE(a.measured);
  EXPECT_NEAR(a.wi.z(), std::cos(30 * M_PI / 180), 1e-12);
  EXPECT_NEAR(a.wi.x(), std::sin(30 * M_PI / 180), 1e-12);
  EXPECT_NEAR(a.wo.x(), -std::sin(45 * M_PI / 180), 1e-12);
  EXPECT_DOUBLE_EQ(a.value[2], 0.125);
  EXPECT_DOUBLE_EQ(a.sigma[1], 0.02);
  EXPECT_EQ(f.samples[1].line, 5);
  EXPECT_NEAR(f.samples[1].wo.y(), std::sin(60 * M_PI / 180), 1e-12);
  EXPECT_TRUE((f.samples[1].sigma == 0).all());
}

TEST(SampleFile, RatiosAreDividedByTheIncidentCosineAndVectorsNormalised) {
  const SampleFile f = parse_samples(
      "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,quantity,r,g,b,sigma\n"
      "0,3,4,0,0,2,ratio,0.8,0.4,0.2,0.08\n"
      "0,0,1,1,0,1,brdf,0.8,0.4,0.2,\n",
      "v.csv");
  ASSERT_EQ(f.samples.size(), 2u);
  EXPECT_NEAR(f.samples[0].wi.norm(), 1, 1e-15);
  EXPECT_NEAR(f.samples[0].value[0], 0.8 / 0.8, 1e-12);  // cos(theta_i) = 4/5
  EXPECT_NEAR(f.samples[0].sigma[2], 0.08 / 0.8, 1e-12);
  EXPECT_DOUBLE_EQ(f.samples[1].value[0], 0.8);
}

TEST(SampleFile, InvalidRowsAreListedByLineOrSkipped) {
  const std::string text =
      "theta_i,phi_i,theta_o,phi_o,r,g,b\n"
      "95,0,10,0,1,1,1\n"
      "10,0,10,0,nan,1,1\n"
      "10,0,10,0,-0.5,1,1\n"
      "10,0,10,0,0.5,1,1\n";
  const std::string message = error_of([&] { parse_samples(text, "bad.csv"); });
  EXPECT_NE(message.find("bad.csv: 3 invalid samples"), std::string::npos) << message;
  EXPECT_NE(message.find("line 2: theta_i = 95 is at or below the horizon"), std::string::npos) << message;
  EXPECT_NE(message.find("line 3: r is not finite"), std::string::npos) << message;
  EXPECT_NE(message.find("line 4: r = -0.5 is negative"), std::string::npos) << message;
  SampleReadOptions skip;
  skip.skip_invalid = true;
  const SampleFile f = parse_samples(text, "bad.csv", skip);
  ASSERT_EQ(f.samples.size(), 1u);
  EXPECT_EQ(f.samples[0].line, 5);
  EXPECT_EQ(f.skipped.size(), 3u);
}

TEST(SampleFile, MalformedFilesNameTheProblem) {
  EXPECT_NE(error_of([] { parse_samples("a,b\n1,2\n", "x.csv"); }).find("names no directions"), std::string::npos);
  EXPECT_NE(error_of([] { parse_samples("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,0.5,abc,1\n", "x.csv"); })
                .find("line 2: column 'g': 'abc' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_samples("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,0.5,,1\n", "x.csv"); })
                .find("all be given or all be empty"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_samples("theta_i,phi_i,theta_o,phi_o,r,g,b,quantity\n1,2,3,4,1,1,1,watts\n", "x.csv"); })
                .find("neither 'brdf' nor 'ratio'"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_samples("# only a comment\n", "x.csv"); }).find("no header row"), std::string::npos);
  EXPECT_NE(error_of([] { parse_samples("theta_i,phi_i,theta_o,phi_o,r,g,b\n", "x.csv"); }).find("no samples"),
            std::string::npos);
}

TEST(SampleFile, ReadsJsonWithSampleNumbers) {
  const SampleFile f = parse_samples(
      R"({"samples": [{"theta_i": 20, "phi_i": 0, "theta_o": 20, "phi_o": 180, "rgb": [0.1, 0.2, 0.3], "sigma": 0.01},
                      {"wi": [0, 0, 2], "wo": [0, 1, 1], "rgb": null},
                      {"wi": [0, 0, 1], "wo": [0, 0, 1], "rgb": [0.5, 0.5, 0.5], "quantity": "ratio", "sigma": [0.1, 0.2, 0.3]}]})",
      "s.json");
  ASSERT_EQ(f.samples.size(), 3u);
  EXPECT_TRUE(f.json);
  EXPECT_DOUBLE_EQ(f.samples[0].sigma[2], 0.01);
  EXPECT_FALSE(f.samples[1].measured);
  EXPECT_EQ(f.measured().size(), 2u);
  EXPECT_DOUBLE_EQ(f.samples[2].sigma[1], 0.2);  // cos(theta_i) = 1
  const std::string message = error_of([] { parse_samples(R"([{"theta_i": 91, "phi_i": 0, "theta_o": 0, "phi_o": 0, "rgb": [1,1,1]}])", "b.json"); });
  EXPECT_NE(message.find("sample 1: theta_i = 91 is at or below the horizon"), std::string::npos) << message;
  EXPECT_NE(error_of([] { parse_samples(std::string(100, '[') + std::string(100, ']'), "deep.json"); }).find("nested deeper"),
            std::string::npos);
}

TEST(SampleFile, APlanWrittenAsCsvReadsBackToTheSameDirections) {
  std::vector<MeasuredSample> plan(2);
  plan[0].wi = Vec3(0.3, -0.4, std::sqrt(1 - 0.25)).normalized();
  plan[0].wo = Vec3(-0.1, 0.2, 0.9).normalized();
  plan[1] = plan[0];
  plan[1].measured = true;
  plan[1].value = Rgb(0.25, 0.5, 2.0);
  plan[1].sigma = Rgb(0.01, 0.02, 0.03);
  const std::string csv = format_samples_csv(plan, {"matlas sample-plan: test"});
  EXPECT_EQ(csv.rfind("# matlas sample-plan: test\n", 0), 0u);
  const SampleFile back = parse_samples(csv, "plan.csv");
  ASSERT_EQ(back.samples.size(), 2u);
  EXPECT_FALSE(back.samples[0].measured);
  EXPECT_LT((back.samples[0].wi - plan[0].wi).norm(), 1e-7);
  EXPECT_LT((back.samples[0].wo - plan[0].wo).norm(), 1e-7);
  EXPECT_TRUE(back.samples[1].measured);
  EXPECT_NEAR(back.samples[1].value[2], 2.0, 1e-9);
  EXPECT_NEAR(back.samples[1].sigma[0], 0.01, 1e-9);
}

}  // namespace
}  // namespace matlas
