// GET /api/preview/status: a scene not prepared yet answers 200 with its progress (and starts
// preparing it), never 503; once ready, previews of it are served.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "small_model.h"
#include "support/temp_dir.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

TEST(PreviewStatus, ASceneBeingPreparedReportsProgressThenIsReady) {
  test::TempDir dir("matlas-preview-status");
  const Model model = test::build_small_model(dir.path(), 6, 3);
  BasisPreviewOptions po;
  po.environments = {"constant"};
  po.objects = {"sphere"};
  po.size = 48;
  po.spp = 16;
  auto previews = std::make_shared<BasisPreviews>(model, po);  // nothing prepared yet
  ServerOptions so;
  so.port = 0;
  so.threads = 4;
  AtlasServer server(model, previews, so);
  server.start();
  httplib::Client c("127.0.0.1", server.port());
  c.set_read_timeout(30, 0);

  auto first = c.Get("/api/preview/status?env=constant&object=sphere");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  nlohmann::json s = nlohmann::json::parse(first->body);
  EXPECT_EQ(s["env"], "constant");
  EXPECT_EQ(s["object"], "sphere");
  EXPECT_FALSE(s["ready"].get<bool>()) << "the first request starts the preparation";
  EXPECT_FALSE(s["stage"].get<std::string>().empty());
  double last = 0;
  const auto start = std::chrono::steady_clock::now();
  while (!s["ready"].get<bool>()) {
    ASSERT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(120));
    ASSERT_FALSE(s.contains("error")) << s.dump();
    const double p = s["progress"].get<double>();
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, 1.0);
    EXPECT_GE(p, last) << "progress never goes back";
    last = p;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    auto r = c.Get("/api/preview/status");  // the defaults: the same scene
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    s = nlohmann::json::parse(r->body);
  }
  EXPECT_DOUBLE_EQ(s["progress"].get<double>(), 1.0);
  const std::vector<double> x = {model.latent()(0, 0), model.latent()(0, 1)};
  auto image = c.Post("/api/preview", nlohmann::json{{"x", x}}.dump(), "application/json");
  ASSERT_TRUE(image);
  EXPECT_EQ(image->status, 200) << "ready means served";
  auto unknown = c.Get("/api/preview/status?env=moon");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 400);
}

}  // namespace
}  // namespace matlas::server
