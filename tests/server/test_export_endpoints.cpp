// The download endpoints (server/export_api.cpp) end to end: POST /api/export as MERL and RGL
// .bsdf, of a point and of a model material; POST /api/fit's report (with the fit's error) and
// POST /api/fit/file's glTF, MaterialX and Blender files, the bytes of the artist writers for the
// reported parameters (and Blender 2.8-3.6's Principled BSDF fitted, "model": "principled-v1");
// bad requests refused with 400 and a message naming the field.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "artist/blender_snippet.h"
#include "artist/gltf_material.h"
#include "artist/materialx_document.h"
#include "artist/pbr_fit.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf_writer.h"
#include "formats/tensor_file.h"
#include "manifold/export.h"
#include "server/atlas_server.h"
#include "support/temp_dir.h"
#include "small_model.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

using nlohmann::json;

class ExportEndpoints : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-server-export");
    model_ = new Model(test::build_small_model(dir_->path(), 5, 23));
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
  static httplib::Result post(const std::string& path, const json& body) {
    httplib::Client c("127.0.0.1", server_->port());
    c.set_read_timeout(120, 0);
    return c.Post(path.c_str(), body.dump(), "application/json");
  }
  static std::vector<double> point(int i) { return {model_->latent()(i, 0), model_->latent()(i, 1)}; }
  static std::vector<double> between(int i, int j) {
    return {0.5 * (point(i)[0] + point(j)[0]), 0.5 * (point(i)[1] + point(j)[1])};
  }
  static Eigen::VectorXd vec(const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  static std::string at_text(const std::vector<double>& x) { return json(x[0]).dump() + "," + json(x[1]).dump(); }
  /// The 400 answer of `body` at `path`, its message containing `part`.
  static void expect_refused(const std::string& path, const json& body, const std::string& part) {
    const auto r = post(path, body);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << r->body;
    const json j = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(j.is_object() && j.contains("error")) << r->body;
    EXPECT_NE(j["error"].get<std::string>().find(part), std::string::npos) << j["error"];
  }

  static test::TempDir* dir_;
  static Model* model_;
  static std::shared_ptr<BasisPreviews> previews_;
  static AtlasServer* server_;
};

test::TempDir* ExportEndpoints::dir_ = nullptr;
Model* ExportEndpoints::model_ = nullptr;
std::shared_ptr<BasisPreviews> ExportEndpoints::previews_;
AtlasServer* ExportEndpoints::server_ = nullptr;

TEST_F(ExportEndpoints, BsdfIsTheRglFileThatMatlasExportWritesForThePoint) {
  const std::vector<double> x = between(1, 2);
  const auto r = post("/api/export", {{"x", x}, {"format", "bsdf"}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/octet-stream");
  EXPECT_NE(r->get_header_value("Content-Disposition").find(".bsdf\""), std::string::npos);
  RglExportOptions options;
  options.description = "matlas export of x = " + at_text(x) + " of m.matlas";
  const std::vector<std::byte> want =
      serialize_tensor_file(rgl_fields_from_table(export_table(*model_, model_->weights(vec(x))), options));
  ASSERT_EQ(r->body.size(), want.size());
  EXPECT_TRUE(std::equal(want.begin(), want.end(), reinterpret_cast<const std::byte*>(r->body.data())));
}

TEST_F(ExportEndpoints, BsdfSpectralIsTheSpectralFileThatMatlasExportWrites) {
  const std::vector<double> x = between(1, 2);
  const auto r = post("/api/export", {{"x", x}, {"format", "bsdf-spectral"}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_NE(r->get_header_value("Content-Disposition").find(".bsdf\""), std::string::npos);
  RglExportOptions options;
  options.description = "matlas export of x = " + at_text(x) + " of m.matlas";
  options.wavelengths = kSpectralExportWavelengths;
  const std::vector<std::byte> want =
      serialize_tensor_file(rgl_fields_from_table(export_table(*model_, model_->weights(vec(x))), options));
  ASSERT_EQ(r->body.size(), want.size());
  EXPECT_TRUE(std::equal(want.begin(), want.end(), reinterpret_cast<const std::byte*>(r->body.data())));
  EXPECT_NE(r->body.find("spectra"), std::string::npos);
  EXPECT_EQ(r->body.find("rgb"), std::string::npos);
}

TEST_F(ExportEndpoints, AModelMaterialIsExportedFromItsOwnTable) {
  const auto r = post("/api/export", {{"x", point(2)}, {"material", 2}, {"format", "binary"}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->body, encode_merl(export_table(*model_, model_->material_weights(2))));
  EXPECT_NE(r->get_header_value("Content-Disposition").find(model_->names()[2] + ".binary"), std::string::npos);
  // No format: MERL, as before.
  const auto plain = post("/api/export", {{"x", point(2)}});
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->body, encode_merl(export_table(*model_, model_->weights(vec(point(2))))));
}

TEST_F(ExportEndpoints, TheFitsReportComesFirstAndItsFilesAreTheWritersBytesOfTheReportedParameters) {
  const std::vector<double> x = between(0, 3);
  const auto r = post("/api/fit", {{"x", x}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json report = json::parse(r->body);
  const std::string source = "x = " + at_text(x) + " of m.matlas", name = "matlas point " + at_text(x);
  EXPECT_EQ(report["source"], source);
  EXPECT_EQ(report["name"], name);
  EXPECT_GE(report["error"]["relative_rms"].get<double>(), 0.0);
  EXPECT_GE(report["error"]["albedo_error"].get<double>(), 0.0);
  EXPECT_TRUE(report["fit"]["converged"].is_boolean());
  EXPECT_TRUE(report.contains("predictive_variance"));
  const json& p = report["parameters"];
  GltfPbr m;
  for (int c = 0; c < 3; ++c) m.base_color[c] = p["base_color"][c].get<double>();
  m.metallic = p["metallic"];
  m.roughness = p["roughness"];
  m.specular = p["specular"];
  m.ior = p["ior"];
  m.clearcoat = p["clearcoat"];
  m.clearcoat_roughness = p["clearcoat_roughness"];

  struct Case {
    std::string format, text;
  };
  for (const Case& c : {Case{"gltf", artist::gltf_material_document(m, name, source)},
                        Case{"mtlx", artist::materialx_document(m, name, source)},
                        Case{"py", artist::blender_snippet(m, name, source)}}) {
    const auto f = post("/api/fit/file", {{"x", x}, {"format", c.format}});
    ASSERT_TRUE(f);
    ASSERT_EQ(f->status, 200) << f->body;
    EXPECT_EQ(f->get_header_value("Content-Type"), "application/octet-stream");
    EXPECT_NE(f->get_header_value("Content-Disposition").find("." + c.format + "\""), std::string::npos);
    EXPECT_EQ(f->body, c.text) << c.format;
  }
  // A material's fit names the material.
  const auto own = post("/api/fit/file", {{"x", point(4)}, {"material", 4}, {"format", "gltf"}});
  ASSERT_TRUE(own);
  ASSERT_EQ(own->status, 200) << own->body;
  EXPECT_EQ(json::parse(own->body)["materials"][0]["name"], model_->names()[4]);
}

TEST_F(ExportEndpoints, ThePrincipledV1FitHasItsOwnReportAndOnlyItsBlenderScript) {
  // "model": "principled-v1": Blender 2.8-3.6's Principled BSDF fitted (artist/pbr_fit.h); the
  // script is the writer's bytes for the reported parameters, kept apart from the glTF fit.
  const std::vector<double> x = between(1, 2);
  const auto r = post("/api/fit", {{"x", x}, {"model", "principled-v1"}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json report = json::parse(r->body);
  EXPECT_EQ(report["kind"], "principled-v1");
  EXPECT_FALSE(report.contains("openpbr_surface"));
  const artist::PrincipledV1FitResult fit = artist::fit_principled_v1(export_table(*model_, model_->weights(vec(x))));
  const std::string source = "x = " + at_text(x) + " of m.matlas", name = "matlas point " + at_text(x);
  const auto f = post("/api/fit/file", {{"x", x}, {"format", "py"}, {"model", "principled-v1"}});
  ASSERT_TRUE(f);
  ASSERT_EQ(f->status, 200) << f->body;
  EXPECT_EQ(f->body, artist::blender_snippet(fit.model, name, source));
  const auto gltf = post("/api/fit", {{"x", x}});
  ASSERT_TRUE(gltf);
  EXPECT_EQ(json::parse(gltf->body)["kind"], "gltf");
  expect_refused("/api/fit/file", {{"x", x}, {"format", "gltf"}, {"model", "principled-v1"}}, "principled-v1");
  expect_refused("/api/fit", {{"x", x}, {"model", "disney"}}, "model");
}

TEST_F(ExportEndpoints, BadRequestsAre400WithAMessageNamingTheField) {
  expect_refused("/api/export", {{"x", point(0)}, {"format", "exr"}}, "format");
  expect_refused("/api/export", {{"x", point(0)}, {"format", 3}}, "format");
  expect_refused("/api/export", {{"x", point(0)}, {"material", 99}}, "material");
  expect_refused("/api/export", {{"x", point(0)}, {"material", -1}}, "material");
  expect_refused("/api/fit", {{"x", {0.0}}}, "x");
  expect_refused("/api/fit", {{"material", 1}}, "x");
  expect_refused("/api/fit", {{"x", point(0)}, {"material", "one"}}, "material");
  expect_refused("/api/fit/file", {{"x", point(0)}}, "format");
  expect_refused("/api/fit/file", {{"x", point(0)}, {"format", "usd"}}, "format");
  expect_refused("/api/fit/file", {{"x", {1e9, 0.0}}, {"format", "gltf"}}, "x");
}

}  // namespace
}  // namespace matlas::server
