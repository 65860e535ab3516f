// A fit's report read back as the fitted BRDF (what `matlas render FIT.json` draws): the same
// values as the model for both kinds of fit, reports without a kind read as glTF fits, and
// reports that are not one refused naming the file and the parameter.
#include <string>

#include <gtest/gtest.h>

#include "artist/fit_report.h"
#include "support/error_of.h"

namespace matlas {
namespace {
namespace fit_report_tests {

Vec3 at(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

template <class Model>
void expect_same_brdf(const Model& m, const BrdfFunction& f) {
  for (const auto& [wi, wo] : {std::pair{at(10, 0), at(25, 170)}, std::pair{at(60, 20), at(50, 230)}, std::pair{at(80, 0), at(5, 90)}})
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f(wi, wo)[c], m(wi, wo)[c], 1e-12 * (1 + m(wi, wo)[c]));
}

/// The error of reading `report` as a fit named fit.json ("no error" if none).
std::string error_of(const nlohmann::json& report) {
  return test::error_of([&] { artist::fitted_brdf(report, "fit.json"); });
}

TEST(FitReport, ReadsBackTheFittedBrdfOfEitherKind) {
  artist::PbrFitResult gltf;
  gltf.model = GltfPbr{Rgb(0.6, 0.3, 0.1), 0.2, 0.35, 0.8, 1.45};
  gltf.model.clearcoat = 0.4;
  gltf.model.clearcoat_roughness = 0.1;
  gltf.model.sheen_color = Rgb::Constant(0.3);
  gltf.model.sheen_roughness = 0.5;
  const nlohmann::json g = artist::fit_report_json("t.binary", gltf, {}, 1.0, std::nullopt);
  EXPECT_EQ(g["kind"], "gltf");
  expect_same_brdf(gltf.model, artist::fitted_brdf(g, "g.json"));
  nlohmann::json older = g;
  older.erase("kind");  // reports written before "kind" existed are glTF fits
  expect_same_brdf(gltf.model, artist::fitted_brdf(older, "old.json"));

  artist::PrincipledV1FitResult v1;
  v1.model.base_color = Rgb(0.2, 0.5, 0.7);
  v1.model.metallic = 0.3;
  v1.model.specular = 0.6;
  v1.model.roughness = 0.25;
  v1.model.sheen = 0.4;
  v1.model.coat = 0.5;
  v1.model.coat_roughness = 0.12;
  const nlohmann::json p = artist::fit_report_json("t.binary", v1, {}, 1.0, std::nullopt);
  EXPECT_EQ(p["kind"], "principled-v1");
  expect_same_brdf(v1.model, artist::fitted_brdf(p, "p.json"));
}

TEST(FitReport, AReportThatIsNotOneIsRefusedNamingTheFileAndParameter) {
  EXPECT_EQ(error_of({{"source", "x"}}), "fit.json: not a fit report of matlas fit (no \"parameters\" object)");
  artist::PrincipledV1FitResult v1;
  nlohmann::json p = artist::fit_report_json("t.binary", v1, {}, 1.0, std::nullopt);
  p["parameters"].erase("coat_roughness");
  EXPECT_EQ(error_of(p), "fit.json: the fit's parameter 'coat_roughness' is missing or not a number");
  p = artist::fit_report_json("t.binary", v1, {}, 1.0, std::nullopt);
  p["parameters"]["sheen"] = 1.5;
  EXPECT_NE(error_of(p).find("fit.json: principled-v1: sheen must be in [0, 1]"), std::string::npos) << error_of(p);
  p["kind"] = "disney";
  EXPECT_EQ(error_of(p), "fit.json: unknown fit kind 'disney' (expected gltf or principled-v1)");
  artist::PbrFitResult gltf;
  nlohmann::json g = artist::fit_report_json("t.binary", gltf, {}, 1.0, std::nullopt);
  g["parameters"]["base_color"] = {0.1, 0.2};
  EXPECT_EQ(error_of(g), "fit.json: the fit's parameter 'base_color' is missing or not three numbers");
}

}  // namespace fit_report_tests
}  // namespace
}  // namespace matlas
