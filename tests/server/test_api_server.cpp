// The HTTP API end to end: a small synthetic model (8x8x16 grid), the real image-basis previews,
// an AtlasServer on an ephemeral loopback port, and cpp-httplib clients.
#include <cmath>
#include <fstream>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "atlas/model_material.h"
#include "brdf/catalog.h"
#include "core/atomic_file.h"
#include "formats/merl_file.h"
#include "formats/synth_database.h"
#include "gp/kernel.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "formats/half_float.h"
#include "manifold/model.h"
#include "zonal/light_table.h"
#include "render/render.h"
#include "render/scene.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "formats/fast_png.h"
#include "support/temp_dir.h"
#include "small_model.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

using nlohmann::json;

class ApiServerTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-server");
    model_ = new Model(test::build_small_model(dir_->path(), 6, 11));
    previews_ = test::sphere_previews(*model_, 32, 2);

    std::filesystem::create_directories(dir_->path() / "www");
    write_file_atomic(dir_->path() / "www" / "index.html", std::string("<p>matlas test page</p>"));
    ServerOptions so;
    so.port = 0;
    so.web_root = dir_->path() / "www";
    so.max_upload_bytes = 1u << 20;
    so.threads = 24;
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
    c.set_read_timeout(30, 0);
    return c;
  }
  static httplib::Result post(const std::string& path, const json& body) {
    return client().Post(path.c_str(), body.dump(), "application/json");
  }
  static std::vector<double> point(int i) {
    return {model_->latent()(i, 0), model_->latent()(i, 1)};
  }
  static Eigen::VectorXd vec(const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  static std::pair<int, int> png_size(const std::string& png) {
    EXPECT_GE(png.size(), 24u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    auto be32 = [&](std::size_t at) {
      return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
             (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
    };
    return {be32(16), be32(20)};
  }
  static void expect_error(const httplib::Result& r, int status) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    const json j = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r->body;
    ASSERT_TRUE(j.contains("error")) << r->body;
    EXPECT_FALSE(j["error"].get<std::string>().empty());
  }

  static test::TempDir* dir_;
  static Model* model_;
  static std::shared_ptr<BasisPreviews> previews_;
  static AtlasServer* server_;
};

test::TempDir* ApiServerTest::dir_ = nullptr;
Model* ApiServerTest::model_ = nullptr;
std::shared_ptr<BasisPreviews> ApiServerTest::previews_;
AtlasServer* ApiServerTest::server_ = nullptr;

TEST_F(ApiServerTest, ModelDescribesNamesLatentPointsAndBounds) {
  auto r = client().Get("/api/model");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json j = json::parse(r->body);
  EXPECT_EQ(j["count"], model_->count());
  EXPECT_EQ(j["dim"], 2);
  EXPECT_EQ(j["names"].get<std::vector<std::string>>(), model_->names());
  for (int i = 0; i < model_->count(); ++i)
    for (int d = 0; d < 2; ++d) EXPECT_DOUBLE_EQ(j["latent"][i][d].get<double>(), model_->latent()(i, d));
  EXPECT_DOUBLE_EQ(j["bounds"]["min"][0].get<double>(), model_->latent_min()[0]);
  EXPECT_DOUBLE_EQ(j["bounds"]["max"][1].get<double>(), model_->latent_max()[1]);
  EXPECT_LT(j["domain"]["min"][0].get<double>(), model_->latent_min()[0]);
  EXPECT_EQ(j["scenes"]["default_env"], "constant");
  // The interpolation mode: the model's (a default build: convex).
  EXPECT_EQ(j["interpolation"], to_string(model_->interpolation()));
  EXPECT_EQ(j["interpolation"], "convex");
  EXPECT_DOUBLE_EQ(j["uncertainty"]["fade_from"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["uncertainty"]["fade_to"].get<double>(), 0.9);
}

TEST_F(ApiServerTest, RepliesAreCompressedWithGzipNeverBrotli) {
  // Brotli at httplib's fixed quality costs about 40x gzip's time (53 s for the interpolation
  // state at n = 1000): a client that accepts both gets gzip, one that accepts only brotli gets
  // the plain body.
  httplib::Client c = client();
  c.set_decompress(false);
  const auto plain = c.Get("/api/model");
  ASSERT_TRUE(plain);
  for (const char* accepted : {"gzip, deflate, br", "br;q=1.0, gzip;q=0.8", "BR,gzip"}) {
    const auto r = c.Get("/api/model", {{"Accept-Encoding", accepted}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->get_header_value("Content-Encoding"), "gzip") << accepted;
    EXPECT_LT(r->body.size(), plain->body.size()) << accepted;
  }
  const auto br = c.Get("/api/model", {{"Accept-Encoding", "br"}});
  ASSERT_TRUE(br);
  EXPECT_FALSE(br->has_header("Content-Encoding"));
  EXPECT_EQ(br->body, plain->body);
}

TEST_F(ApiServerTest, PreviewIsTheImageBasisComposedAtTheWeightsOfX) {
  const auto a = point(0), b = point(1);
  const std::vector<double> mid = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
  auto r = post("/api/preview", {{"x", mid}, {"size", 32}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "image/png");
  const std::string expected =
      encode_png_fast(previews_->render(model_->weights(vec(mid)), "constant", "sphere", 32), previews_->tone());
  EXPECT_EQ(r->body, expected);
  EXPECT_EQ(png_size(r->body), std::make_pair(32, 32));

  auto other = post("/api/preview", {{"x", a}, {"size", 32}});
  ASSERT_TRUE(other);
  EXPECT_NE(other->body, r->body);
  auto small = post("/api/preview", {{"x", mid}, {"size", 16}});
  ASSERT_TRUE(small);
  EXPECT_EQ(png_size(small->body), std::make_pair(16, 16));
}

TEST_F(ApiServerTest, RefinementAtRestAddsSamplesAndItsErrorFalls) {
  const auto a = point(0), b = point(1);
  const std::vector<double> mid = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
  auto first = post("/api/preview/refine", {{"x", mid}, {"seconds", 0.05}});
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  EXPECT_EQ(first->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(png_size(first->body), std::make_pair(32, 32));  // the full preview size
  const int first_spp = std::stoi(first->get_header_value("X-Matlas-Spp"));
  EXPECT_GE(first_spp, 16);
  int spp = first_spp;
  double first_error = 0, error = 0;
  bool converged = false;
  // Until converged: 0.2 s per request, at most a minute (a sanitizer build beside other tests
  // needs more than the dozen seconds a Release build does).
  for (int i = 0; i < 300 && !converged; ++i) {
    auto r = post("/api/preview/refine", {{"x", mid}, {"seconds", 0.2}});
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const int now = std::stoi(r->get_header_value("X-Matlas-Spp"));
    EXPECT_GT(now, spp);  // the same point: the same refinement, more samples
    spp = now;
    // "unknown" until the refinement has passes enough to estimate its error (a slow build's
    // first 0.2 s may give one).
    const std::string estimate = r->get_header_value("X-Matlas-Error");
    if (estimate == "unknown") continue;
    error = std::stod(estimate);
    if (first_error == 0) first_error = error;
    converged = r->get_header_value("X-Matlas-Converged") == "1";
  }
  EXPECT_TRUE(converged) << spp << " spp, error " << error;
  EXPECT_LE(error, 0.004);
  EXPECT_LT(error, first_error);
  // The refined image is the point's material: its mean over the object agrees with a direct
  // render of the table at the database's sampling (independent samples, 256 spp).
  const Eigen::VectorXd w = model_->weights(vec(mid));
  const PreviewSource::Refined refined = previews_->refine(w, "test-direct", "constant", "sphere", 1.0, false);
  render::SceneDescription desc;
  desc.environment = "constant";
  const render::Scene scene(desc);
  render::RenderSettings rs;
  rs.width = rs.height = 32;
  rs.spp = 256;
  rs.seed = 99;
  const Image direct = render::render(scene, atlas::ModelTableMaterial(*model_, w), rs);
  const std::vector<float> coverage = render::object_coverage(scene, rs);
  for (int c = 0; c < 3; ++c) {
    double r_sum = 0, d_sum = 0;
    for (std::size_t p = 0; p < coverage.size(); ++p)
      if (coverage[p] == 1.0f) r_sum += refined.image.rgb[3 * p + c], d_sum += direct.rgb[3 * p + c];
    EXPECT_NEAR(r_sum / d_sum, 1.0, 0.02) << "channel " << c;
  }
  // Another point starts its own refinement.
  auto other = post("/api/preview/refine", {{"x", a}, {"seconds", 0.05}});
  ASSERT_TRUE(other);
  EXPECT_LT(std::stoi(other->get_header_value("X-Matlas-Spp")), spp);
  expect_error(post("/api/preview/refine", {{"x", mid}, {"seconds", 60}}), 400);
  expect_error(post("/api/preview/refine", {{"x", mid}, {"env", "moon"}}), 400);
}

TEST_F(ApiServerTest, ADenoisedRefinementIsMarkedAndKeepsTheImage) {
  // "denoise": the same refinement's image denoised from its halves, marked as such, with its own
  // error estimate below the plain one; the object's mean stays that of the plain image.
  const auto a = point(0), b = point(2);
  const std::vector<double> mid = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
  auto plain = post("/api/preview/refine", {{"x", mid}, {"seconds", 0.05}});
  ASSERT_TRUE(plain);
  EXPECT_TRUE(plain->get_header_value("X-Matlas-Denoised").empty());  // after one pass: nothing to denoise
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(post("/api/preview/refine", {{"x", mid}, {"seconds", 0.05}}));
  auto denoised = post("/api/preview/refine", {{"x", mid}, {"seconds", 0.05}, {"denoise", true}});
  ASSERT_TRUE(denoised);
  ASSERT_EQ(denoised->status, 200) << denoised->body;
  EXPECT_EQ(denoised->get_header_value("X-Matlas-Denoised"), "1");
  const double plain_error = std::stod(denoised->get_header_value("X-Matlas-Error"));
  const double denoised_error = std::stod(denoised->get_header_value("X-Matlas-Denoised-Error"));
  EXPECT_LT(denoised_error, plain_error);
  EXPECT_GT(denoised_error, 0.0);
  EXPECT_EQ(png_size(denoised->body), std::make_pair(32, 32));
  const Eigen::VectorXd w = model_->weights(vec(mid));
  const PreviewSource::Refined d = previews_->refine(w, "test-denoise", "constant", "sphere", 0.5, true);
  const PreviewSource::Refined p = previews_->refine(w, "test-denoise", "constant", "sphere", 0.05, false);
  ASSERT_TRUE(d.denoised);
  ASSERT_FALSE(p.denoised);
  double d_sum = 0, p_sum = 0;
  for (std::size_t i = 0; i < d.image.rgb.size(); ++i) d_sum += d.image.rgb[i], p_sum += p.image.rgb[i];
  EXPECT_NEAR(d_sum / p_sum, 1.0, 0.02);
  expect_error(post("/api/preview/refine", {{"x", mid}, {"denoise", "yes"}}), 400);
}

TEST_F(ApiServerTest, WeightsAtAMaterialPointSelectThatMaterial) {
  auto r = post("/api/weights", {{"x", point(2)}, {"top", 3}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json j = json::parse(r->body);
  ASSERT_EQ(j["weights"].size(), static_cast<std::size_t>(model_->count()));
  for (int i = 0; i < model_->count(); ++i) EXPECT_NEAR(j["weights"][i].get<double>(), i == 2 ? 1.0 : 0.0, 1e-6);
  EXPECT_LT(j["variance"].get<double>(), 1e-3);
  EXPECT_EQ(j["top"][0]["index"], 2);
  EXPECT_EQ(j["top"][0]["name"], model_->names()[2]);
  EXPECT_EQ(j["top"].size(), 3u);
  // A database material is plausible: no negative values, its albedo curve's range.
  const json& p = j["plausibility"];
  EXPECT_TRUE(p["plausible"].get<bool>()) << p.dump();
  EXPECT_EQ(p["negative_fraction"].get<double>(), 0.0);
  EXPECT_GT(p["sampled_values"].get<int>(), 0);
  double hi = 0;
  for (const Rgb& a : model_->albedo_curve(model_->material_weights(2))) hi = std::max(hi, a.maxCoeff());
  EXPECT_NEAR(p["max_albedo"].get<double>(), hi, 1e-12);
}

TEST_F(ApiServerTest, RealtimeLightTableIsTheLightTableOfThePointsTable) {
  auto r = post("/api/realtime/lights", {{"x", point(2)}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const zonal::LightTable expected = zonal::LightTable::reduce(model_->table(model_->material_weights(2)));
  ASSERT_EQ(r->body.size(), 2 * expected.values().size());
  double largest = 0, worst = 0;
  for (std::size_t v = 0; v < expected.values().size(); ++v) {
    const auto lo = static_cast<unsigned char>(r->body[2 * v]), hi = static_cast<unsigned char>(r->body[2 * v + 1]);
    const float got = half_to_float(static_cast<std::uint16_t>(lo | (hi << 8)));
    largest = std::max(largest, static_cast<double>(std::abs(expected.values()[v])));
    worst = std::max(worst, static_cast<double>(std::abs(got - expected.values()[v])));
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 2e-3 * largest);  // float16 storage and answer
  // /api/realtime names the grid; a point of the wrong dimension is refused.
  const json info = json::parse(client().Get("/api/realtime")->body);
  EXPECT_EQ(info["light_table"]["theta_h"].get<int>() * info["light_table"]["theta_d"].get<int>() *
                info["light_table"]["phi_d"].get<int>() * 3,
            static_cast<int>(expected.values().size()));
  expect_error(post("/api/realtime/lights", {{"x", {0.1, 0.2, 0.3}}}), 400);
}

TEST_F(ApiServerTest, InterpolationDataRebuildTheModelsCovarianceAndMetric) {
  auto r = client().Get("/api/interpolation");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json j = json::parse(r->body);
  const int n = model_->count(), q = model_->dim();
  EXPECT_EQ(j["mode"], std::string(to_string(model_->interpolation())));
  ASSERT_EQ(j["latent"].size(), static_cast<std::size_t>(n));
  Eigen::MatrixXd X(n, q);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < q; ++d) X(i, d) = j["latent"][i][d].get<double>();
  EXPECT_EQ(X, model_->latent());  // printed with round-trip precision
  const gp::Kernel k{j["lengthscale"].get<double>(), j["nugget"].get<double>()};
  EXPECT_EQ(k.lengthscale, model_->posterior().kernel().lengthscale);
  EXPECT_EQ(k.nugget, model_->posterior().kernel().nugget);
  // The factor is lower triangular and L L^T is the covariance of the points, computed here anew.
  const auto matrix = [&](const char* key) {
    EXPECT_EQ(j[key].size(), static_cast<std::size_t>(n * n)) << key;
    Eigen::MatrixXd m(n, n);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) m(a, b) = j[key][static_cast<std::size_t>(a * n + b)].get<double>();
    return m;
  };
  const Eigen::MatrixXd L = matrix("cholesky");
  EXPECT_EQ(L.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((L * L.transpose() - gp::covariance_matrix(X, k)).cwiseAbs().maxCoeff(), 1e-12);
  // The metric: the centred layout Gram over its mean diagonal, plus the ridge (gp/convex_weights.h).
  const Eigen::MatrixXd A = matrix("metric");
  EXPECT_EQ(A, model_->convex_metric());
  EXPECT_LT((A - A.transpose()).cwiseAbs().maxCoeff(), 1e-15);
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(j["taper_radius"][i].get<double>(), model_->posterior().taper_radius()[i], 0.0);
}

TEST_F(ApiServerTest, ExportIsAMerlTableOfThePoint) {
  const std::vector<double> x = {point(3)[0] * 0.6 + point(4)[0] * 0.4, point(3)[1] * 0.6 + point(4)[1] * 0.4};
  auto r = post("/api/export", {{"x", x}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_NE(r->get_header_value("Content-Disposition").find(".binary"), std::string::npos);
  const auto path = dir_->path() / "export.binary";
  write_file_atomic(path, r->body);
  const BrdfTable got = read_merl(path);
  ASSERT_EQ(got.dims(), model_->dims());
  const BrdfTable want = model_->table(model_->weights(vec(x)));
  std::size_t checked = 0;
  for (std::size_t v = 0; v < want.size(); ++v) {
    const double w = want.stored()[v], g = got.stored()[v];
    if (!model_->kept(v)) EXPECT_LT(g, 0.0);  // dropped column: missing
    else if (w < 0) EXPECT_EQ(g, 0.0);        // clamped: a MERL reader takes negatives as missing
    else {
      EXPECT_DOUBLE_EQ(g, w);
      ++checked;
    }
  }
  EXPECT_GT(checked, want.size() / 2);
}

TEST_F(ApiServerTest, ProjectionOfADatabaseFilePutsItAtItsLatentPoint) {
  const std::string bytes = read_file(model_->path().parent_path() / "db" / (model_->names()[3] + ".binary"));
  auto r = client().Post("/api/project", bytes, "application/octet-stream");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json j = json::parse(r->body);
  const Eigen::VectorXd extent = model_->latent_max() - model_->latent_min();
  for (int d = 0; d < 2; ++d) EXPECT_NEAR(j["x"][d].get<double>(), point(3)[static_cast<std::size_t>(d)], 0.02 * extent[d]);
  EXPECT_LT(j["residual"].get<double>(), 0.02);
  EXPECT_EQ(j["nearest"]["index"], 3);

  // Also as a multipart form upload (field "file").
  httplib::MultipartFormDataItems items = {{"file", bytes, "m.binary", "application/octet-stream"}};
  auto m = client().Post("/api/project", items);
  ASSERT_TRUE(m);
  ASSERT_EQ(m->status, 200) << m->body;
  EXPECT_NEAR(json::parse(m->body)["x"][0].get<double>(), j["x"][0].get<double>(), 1e-9);
}

TEST_F(ApiServerTest, PanelsSliceLobeAlbedoAndMapLayers) {
  const auto x = point(1);
  auto s = post("/api/slice", {{"x", x}, {"phi_d", 45}});
  ASSERT_TRUE(s);
  ASSERT_EQ(s->status, 200) << s->body;
  EXPECT_EQ(png_size(s->body), std::make_pair(model_->dims().theta_h, model_->dims().theta_d));

  auto l = post("/api/lobe", {{"x", x}, {"theta_i", 40}, {"samples", 37}});
  ASSERT_TRUE(l);
  const json lobe = json::parse(l->body);
  ASSERT_EQ(lobe["theta_o"].size(), 37u);
  EXPECT_NEAR(lobe["theta_o"][18].get<double>(), 0.0, 1e-12);
  // theta_o = 0 lies in the plane of incidence: f(wi, normal) through the model.
  const double ti = 40 * kPi / 180;
  const Rgb f = model_->lookup(Vec3(-std::sin(ti), 0, std::cos(ti)), Vec3(0, 0, 1), model_->weights(vec(x)));
  EXPECT_NEAR(lobe["rgb"][18][1].get<double>(), std::max(0.0, f[1]), 1e-12);

  auto a = post("/api/albedo", {{"x", x}});
  ASSERT_TRUE(a);
  const json albedo = json::parse(a->body);
  const auto curve = model_->albedo_curve(model_->weights(vec(x)));
  ASSERT_EQ(albedo["rgb"].size(), curve.size());
  EXPECT_NEAR(albedo["rgb"][10][2].get<double>(), curve[10][2], 1e-12);

  for (const char* layer : {"albedo", "variance", "plausibility"}) {
    auto m = post("/api/map", {{"layer", layer}, {"axes", {0, 1}}, {"x", x}, {"rect", {-1, 1, -1, 1}}, {"size", {24, 16}}});
    ASSERT_TRUE(m);
    ASSERT_EQ(m->status, 200) << m->body;
    EXPECT_EQ(png_size(m->body), std::make_pair(24, 16));
  }

  auto t = client().Get("/api/thumbnail/2?size=24");
  ASSERT_TRUE(t);
  ASSERT_EQ(t->status, 200) << t->body;
  EXPECT_EQ(png_size(t->body), std::make_pair(24, 24));
}

TEST_F(ApiServerTest, BadRequestsGet4xxWithAMessage) {
  expect_error(post("/api/preview", {{"x", {0.0}}}), 400);                          // wrong dimension
  expect_error(post("/api/preview", {{"x", {1e9, 0.0}}}), 400);                     // out of range
  expect_error(post("/api/weights", {{"x", {0.0, "a"}}}), 400);                     // not a number
  expect_error(post("/api/export", {{"y", {0.0, 0.0}}}), 400);                      // missing field
  expect_error(post("/api/preview", {{"x", point(0)}, {"env", "moon"}}), 400);      // unknown scene
  expect_error(post("/api/preview", {{"x", point(0)}, {"size", 100000}}), 400);     // size
  expect_error(post("/api/map", {{"x", point(0)}, {"rect", {1, 0, 0, 1}}}), 400);    // empty rect
  expect_error(client().Post("/api/weights", "{\"x\": [0, NaN]}", "application/json"), 400);
  expect_error(client().Post("/api/weights", "{\"x\": [0, 0", "application/json"), 400);
  expect_error(client().Post("/api/project", std::string(2u << 20, 'a'), "application/octet-stream"), 413);
  expect_error(client().Post("/api/project", std::string(1000, 'a'), "application/octet-stream"), 422);
  expect_error(client().Post("/api/project", "", "application/octet-stream"), 400);
  expect_error(client().Get("/api/thumbnail/999"), 404);
  expect_error(client().Get("/api/nothing"), 404);
  // The server is still fine.
  auto r = client().Get("/api/model");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
}

TEST_F(ApiServerTest, ServesTheWebRoot) {
  auto r = client().Get("/");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("matlas test page"), std::string::npos);
}

TEST_F(ApiServerTest, ManyConcurrentClientsAllGetTheirPreviews) {
  const Eigen::VectorXd lo = model_->latent_min(), hi = model_->latent_max();
  std::atomic<int> ok{0}, failed{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 12; ++t)
    threads.emplace_back([&, t] {
      std::mt19937 rng(static_cast<unsigned>(t));
      std::uniform_real_distribution<double> u(0, 1);
      auto c = client();
      for (int k = 0; k < 8; ++k) {
        const json body = {{"x", {lo[0] + u(rng) * (hi[0] - lo[0]), lo[1] + u(rng) * (hi[1] - lo[1])}}, {"size", 16}};
        auto r = c.Post("/api/preview", body.dump(), "application/json");
        (r && r->status == 200 && r->body.substr(1, 3) == "PNG" ? ok : failed)++;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(ok.load(), 96);
  EXPECT_EQ(failed.load(), 0);
}

}  // namespace
}  // namespace matlas::server
