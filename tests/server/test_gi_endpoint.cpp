// GET /api/gi, the scene view, end to end: a small synthetic model, GI scenes traced on demand
// at a tiny size, an AtlasServer on an ephemeral port, and cpp-httplib clients.
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "atlas/gi_basis.h"
#include "core/error.h"
#include "formats/fast_png.h"
#include "manifold/model.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/world.h"
#include "render/auto_exposure.h"
#include "render/firefly_filter.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "server/gi_scenes.h"
#include "small_model.h"
#include "support/temp_dir.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

/// The composed image as GET /api/gi serves it: its fireflies removed (render/firefly_filter.h).
Image filtered(Image image) {
  render::remove_fireflies(image);
  return image;
}

using nlohmann::json;

class GiEndpointTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-gi-server");
    model_ = new Model(test::build_small_model(dir_->path(), 5, 3));
    previews_ = test::sphere_previews(*model_, 16, 1);

    GiSceneOptions go;
    go.scenes = {"floor", "box"};
    go.trace.width = 24;
    go.trace.height = 16;
    go.trace.spp = 2;
    go.batch = 4;  // two passes for the 6 images
    go.refine_width = 48;  // the refined view: 48 x 32
    gi_ = std::make_shared<GiScenes>(*model_, go);
    ServerOptions so;
    so.port = 0;
    so.threads = 8;
    so.gi_scenes = [](const Model&) { return gi_; };
    server_ = new AtlasServer(*model_, previews_, so);
    server_->start();
  }
  static void TearDownTestSuite() {
    delete server_;
    gi_.reset();
    previews_.reset();
    delete model_;
    delete dir_;
  }

  static httplib::Result get(const std::string& path, const AtlasServer& server = *server_) {
    httplib::Client c("127.0.0.1", server.port());
    c.set_read_timeout(60, 0);
    return c.Get(path.c_str());
  }
  static std::string point_text(int i) {
    return std::to_string(model_->latent()(i, 0)) + "," + std::to_string(model_->latent()(i, 1));
  }
  static std::string error_of(const httplib::Result& r) { return json::parse(r->body).at("error").get<std::string>(); }

  static test::TempDir* dir_;
  static Model* model_;
  static std::shared_ptr<BasisPreviews> previews_;
  static std::shared_ptr<GiScenes> gi_;
  static AtlasServer* server_;
};

test::TempDir* GiEndpointTest::dir_ = nullptr;
Model* GiEndpointTest::model_ = nullptr;
std::shared_ptr<BasisPreviews> GiEndpointTest::previews_;
std::shared_ptr<GiScenes> GiEndpointTest::gi_;
AtlasServer* GiEndpointTest::server_ = nullptr;

TEST_F(GiEndpointTest, ModelInfoListsTheScenes) {
  const auto r = get("/api/model");
  ASSERT_TRUE(r);
  const json j = json::parse(r->body);
  EXPECT_EQ(j["gi"]["scenes"], json({"floor", "box"}));
  EXPECT_EQ(j["gi"]["preloaded"], json::array());
  EXPECT_EQ(j["gi"]["views"]["floor"], json({"front", "side", "above"}));
  EXPECT_EQ(j["gi"]["views"]["box"], json({"front", "side", "above"}));
}

TEST_F(GiEndpointTest, RefinementAtRestAddsSamplesAndSendsTheRefinedImage) {
  // In "floor": "box" is first asked for by the test of a scene being traced (one process may run them all).
  const Eigen::Vector2d x(0.5 * (model_->latent()(0, 0) + model_->latent()(2, 0)), 0.5 * (model_->latent()(0, 1) + model_->latent()(2, 1)));
  const std::string body = json{{"scene", "floor"}, {"x", {x[0], x[1]}}, {"seconds", 0.05}, {"exposure", -1}, {"tone", "clamp"}}.dump();
  httplib::Client c("127.0.0.1", server_->port());
  c.set_read_timeout(60, 0);
  const auto first = c.Post("/api/gi/refine", body, "application/json");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  const int spp1 = std::stoi(first->get_header_value("X-Matlas-Spp"));
  EXPECT_GE(spp1, 1);
  const auto second = c.Post("/api/gi/refine", body, "application/json");
  ASSERT_EQ(second->status, 200) << second->body;
  const int spp2 = std::stoi(second->get_header_value("X-Matlas-Spp"));
  EXPECT_GT(spp2, spp1) << "a second call adds passes";
  EXPECT_NE(second->get_header_value("X-Matlas-Error"), "unknown") << "two passes give an error estimate";
  // The PNG is the library's refinement of that point (a direct trace of m(x) at 48 x 32),
  // tone-mapped as asked.
  char key[80];
  std::snprintf(key, sizeof key, "%.17g,%.17g,", x[0], x[1]);
  const auto refined = gi_->refined("floor", key, false);
  ASSERT_TRUE(refined.has_value());
  EXPECT_EQ(refined->state.spp, spp2);
  EXPECT_EQ(refined->image.width, 48);
  EXPECT_EQ(refined->image.height, 32);
  EXPECT_FALSE(refined->denoised);
  EXPECT_EQ(second->body, encode_png_fast(refined->image, ToneMap{ToneMap::Curve::clamp, -1.0}));
  EXPECT_FALSE(second->has_header("X-Matlas-Denoised"));
  // Denoised on request (two passes are in): the library's denoised refinement, marked so, with
  // the noise it estimates left below the plain mean's.
  const std::string denoise_body = json{{"scene", "floor"}, {"x", {x[0], x[1]}}, {"seconds", 0.05}, {"exposure", -1},
                                        {"tone", "clamp"}, {"denoise", true}}.dump();
  const auto third = c.Post("/api/gi/refine", denoise_body, "application/json");
  ASSERT_EQ(third->status, 200) << third->body;
  EXPECT_EQ(third->get_header_value("X-Matlas-Denoised"), "1");
  const auto denoised = gi_->refined("floor", key, true);
  ASSERT_TRUE(denoised.has_value());
  EXPECT_TRUE(denoised->denoised);
  EXPECT_EQ(third->body, encode_png_fast(denoised->image, ToneMap{ToneMap::Curve::clamp, -1.0}));
  EXPECT_LT(std::stod(third->get_header_value("X-Matlas-Denoised-Error")),
            std::stod(third->get_header_value("X-Matlas-Error")));
  EXPECT_NE(denoised->image.rgb, gi_->refined("floor", key, false)->image.rgb);
  // Bad requests name what is wrong.
  EXPECT_EQ(c.Post("/api/gi/refine", R"({"scene": "attic", "x": [0, 0]})", "application/json")->status, 400);
  EXPECT_EQ(c.Post("/api/gi/refine", R"({"scene": "floor", "x": [0, 0], "tone": "sepia"})", "application/json")->status, 400);
  EXPECT_EQ(c.Post("/api/gi/refine", R"({"scene": "floor"})", "application/json")->status, 400);
}

TEST_F(GiEndpointTest, ViewsOfABuiltInSceneAreScenesOfTheirOwn) {
  gi_->wait("floor");
  gi_->wait("floor@side");
  const auto front = get("/api/gi?scene=floor&exposure=0&x=" + point_text(1));
  const auto side = get("/api/gi?scene=floor@side&exposure=0&x=" + point_text(1));
  ASSERT_EQ(front->status, 200);
  ASSERT_EQ(side->status, 200);
  EXPECT_NE(front->body, side->body);
  EXPECT_EQ(atlas::gi_basis_scene_name(*gi_->wait("floor@side")), "floor@side");
  EXPECT_EQ(get("/api/gi?scene=floor@under&x=" + point_text(1))->status, 400);
  EXPECT_EQ(get("/api/gi?scene=attic@side&x=" + point_text(1))->status, 400);
}

TEST_F(GiEndpointTest, UnknownSceneIs400NamingTheOfferedOnes) {
  const auto r = get("/api/gi?scene=attic&x=" + point_text(0));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  const std::string e = error_of(r);
  EXPECT_NE(e.find("\"attic\""), std::string::npos) << e;
  EXPECT_NE(e.find("floor, box"), std::string::npos) << e;
}

TEST_F(GiEndpointTest, BadPointsAre400NamingTheParameter) {
  for (const std::string x : {"", "0.1", "0.1,abc", "1e9,0", "nan,0"}) {
    const auto r = get("/api/gi?scene=floor&x=" + x);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << x;
    EXPECT_NE(error_of(r).find("x"), std::string::npos) << error_of(r);
  }
  const auto r = get("/api/gi?scene=floor&x=" + point_text(0) + "&exposure=99");
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(error_of(r).find("exposure"), std::string::npos);
}

TEST_F(GiEndpointTest, ASceneBeingTracedIs503WithProgressThenTheLibrarysComposition) {
  // The first request of a scene queues it: 503 with what is being done, however fast the trace.
  const auto first = get("/api/gi?scene=box&x=" + point_text(1));
  ASSERT_TRUE(first);
  EXPECT_EQ(first->status, 503);
  EXPECT_NE(error_of(first).find("being prepared"), std::string::npos) << error_of(first);
  EXPECT_TRUE(first->has_header("X-Matlas-Progress"));
  gi_->wait("box");
  const std::filesystem::path file = gi_->basis_path("box");
  ASSERT_TRUE(std::filesystem::exists(file));
  EXPECT_EQ(file.parent_path(), std::filesystem::path(model_->path().string() + ".gi"));  // beside the model

  // The library's composition, from the file on disk, at the model's weights of the point.
  const atlas::GiBasis basis = atlas::GiBasis::load(file);
  EXPECT_EQ(basis.width(), 24);
  for (const double exposure : {0.0, -1.5}) {
    Eigen::Vector2d x(0.3 * model_->latent()(1, 0) + 0.7 * model_->latent()(2, 0),
                      0.3 * model_->latent()(1, 1) + 0.7 * model_->latent()(2, 1));
    char query[160];
    std::snprintf(query, sizeof query, "/api/gi?scene=box&x=%.17g,%.17g&exposure=%g", x[0], x[1], exposure);
    const auto r = get(query);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "image/png");
    const std::string expected =
        encode_png_fast(filtered(basis.compose(model_->weights(x))), ToneMap{ToneMap::Curve::aces, exposure});
    EXPECT_EQ(r->body, expected) << "exposure " << exposure;
    Image fireflies = basis.compose(model_->weights(x));
    EXPECT_EQ(r->get_header_value("X-Matlas-Fireflies"), std::to_string(render::remove_fireflies(fireflies)));
  }
  // Different points, different images.
  const auto a = get("/api/gi?scene=box&x=" + point_text(0)), b = get("/api/gi?scene=box&x=" + point_text(3));
  ASSERT_EQ(a->status, 200);
  EXPECT_NE(a->body, b->body);

  // exposure=auto: the scene's key with the mean material (one value for every point), any tone curve.
  const double key = render::auto_exposure(basis.compose(Eigen::VectorXd::Zero(model_->count())));
  for (const auto& [name, curve] : {std::pair{"reinhard", ToneMap::Curve::reinhard}, std::pair{"aces", ToneMap::Curve::aces}}) {
    const auto r = get("/api/gi?scene=box&exposure=auto&tone=" + std::string(name) + "&x=" + point_text(3));
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_NEAR(std::stod(r->get_header_value("X-Matlas-Exposure")), key, 1e-3);
    EXPECT_EQ(r->body, encode_png_fast(filtered(basis.compose(model_->weights(Eigen::Vector2d(std::stod(std::to_string(model_->latent()(3, 0))), std::stod(std::to_string(model_->latent()(3, 1))))))), ToneMap{curve, key}));
  }
  EXPECT_EQ(get("/api/gi?scene=box&tone=sepia&x=" + point_text(3))->status, 400);
  EXPECT_EQ(get("/api/gi?scene=box&exposure=bright&x=" + point_text(3))->status, 400);
}

TEST_F(GiEndpointTest, AGivenBasisIsServedAtOnceAndOneOfAnotherModelIsRefused) {
  // A basis made as `matlas gi-basis` makes it, served through GiSceneOptions::bases.
  pathtrace::TraceSettings t;
  t.width = 16;
  t.height = 12;
  t.spp = 1;
  const pathtrace::World world(pathtrace::load_scene("box", "sphere"));  // no environment map: no assets needed
  const auto file = dir_->path() / "given.gi";
  atlas::open_or_build_gi_basis(*model_, world, t, file, 8);
  GiSceneOptions go;
  go.bases = {file};
  go.scenes.clear();
  auto gi = std::make_shared<GiScenes>(*model_, go);
  EXPECT_EQ(gi->scenes(), std::vector<std::string>{"box"});
  EXPECT_EQ(gi->preloaded(), std::vector<std::string>{"box"});
  ServerOptions so;
  so.port = 0;
  so.gi_scenes = [gi](const Model&) { return gi; };
  AtlasServer server(*model_, previews_, so);
  server.start();
  const auto r = get("/api/gi?x=" + point_text(2), server);  // the first scene by default
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->body, encode_png_fast(filtered(atlas::GiBasis::load(file).compose(model_->material_weights(2))),
                                     ToneMap{ToneMap::Curve::aces, 0.0}));
  EXPECT_EQ(get("/api/gi?scene=floor&x=" + point_text(2), server)->status, 400);  // not offered here

  // Another model (other materials): its basis is refused, naming the file.
  const Model other = test::build_small_model(dir_->path(), 5, 99, "other.matlas", "db2");
  try {
    GiScenes refused(other, go);
    FAIL() << "a basis of another model was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("given.gi"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("another model"), std::string::npos) << e.what();
  }
}

TEST_F(GiEndpointTest, WithoutScenesTheEndpointIs404SayingHowToGetThem) {
  ServerOptions so;
  so.port = 0;
  AtlasServer server(*model_, previews_, so);
  server.start();
  const auto r = get("/api/gi?scene=floor&x=" + point_text(0), server);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_NE(error_of(r).find("--gi-basis"), std::string::npos) << error_of(r);
  EXPECT_FALSE(json::parse(get("/api/model", server)->body).contains("gi"));
}

}  // namespace
}  // namespace matlas::server
