// The refinement of the preview at rest (POST /api/preview/refine): a newer preview or map layer
// request from the same client interrupts the pass under way (200 with the state so far,
// X-Matlas-Interrupted), one from another client does not.
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <utility>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server/atlas_server.h"
#include "server/preview_generations.h"
#include "server/preview_source.h"
#include "small_model.h"
#include "support/temp_dir.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

TEST(PreviewGenerations, OnlyTheSameClientsNextPreviewSupersedes) {
  PreviewGenerations g;
  SupersededSink sink(g, "10.0.0.1", g.current("10.0.0.1"));
  EXPECT_NO_THROW(sink.update("render", 1, 2));
  g.advance("10.0.0.2");
  EXPECT_NO_THROW(sink.update("render", 1, 2));
  g.advance("10.0.0.1");
  EXPECT_THROW(sink.update("render", 1, 2), PreviewSource::Interrupt);
  EXPECT_EQ(g.current("10.0.0.1"), 1u);
  EXPECT_EQ(g.current("10.0.0.3"), 0u);
}

/// A preview source whose refinement reports progress for up to 20 s (until interrupted).
class SlowRefineSource final : public PreviewSource {
public:
  std::vector<std::string> environments() const override { return {"constant"}; }
  std::vector<std::string> objects() const override { return {"sphere"}; }
  std::string default_environment() const override { return "constant"; }
  std::string default_object() const override { return "sphere"; }
  int size() const override { return 16; }
  int drag_size() const override { return 8; }
  ToneMap tone() const override { return {}; }
  Image render(const Eigen::VectorXd&, const std::string&, const std::string&, int size) const override {
    return Image(size, size);
  }
  Refined refine(const Eigen::VectorXd&, const std::string&, const std::string&, const std::string&, double, bool,
                 ProgressSink& progress) const override {
    refining = true;
    const auto start = std::chrono::steady_clock::now();
    try {
      while (std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
        progress.update("render", 0, 1);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    } catch (const Interrupt&) {
      return Refined{Image(16, 16), {}, true, false};
    }
    return Refined{Image(16, 16), {}, false, false};
  }
  mutable std::atomic<bool> refining{false};
};

/// Starts a refinement of 5 s at material 0's point, then sends `path` with `body` (made from that
/// point) from the same client: the refinement's status and X-Matlas-Interrupted, the request's status.
std::pair<std::string, int> refinement_after(const std::string& path,
                                             const std::function<std::string(const std::vector<double>&)>& body) {
  test::TempDir dir("matlas-refine");
  const Model model = test::build_small_model(dir.path(), 4, 5);
  auto source = std::make_shared<SlowRefineSource>();
  ServerOptions so;
  so.port = 0;
  so.threads = 4;
  AtlasServer server(model, source, so);
  server.start();
  const std::vector<double> x = {model.latent()(0, 0), model.latent()(0, 1)};
  const std::string refine_body = nlohmann::json{{"x", x}, {"seconds", 5}}.dump();

  const auto started = std::chrono::steady_clock::now();
  auto refine = std::async(std::launch::async, [&] {
    httplib::Client c("127.0.0.1", server.port());
    c.set_read_timeout(30, 0);
    auto r = c.Post("/api/preview/refine", refine_body, "application/json");
    return r ? std::to_string(r->status) + " " + r->get_header_value("X-Matlas-Interrupted") : std::string("none");
  });
  while (!source->refining) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  httplib::Client c("127.0.0.1", server.port());
  auto next = c.Post(path, body(x), "application/json");
  const std::string refined = refine.get();
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(10));
  return {refined, next ? next->status : -1};
}

TEST(PreviewRefinement, ANewPreviewFromTheSameClientInterruptsTheRefinement) {
  const auto [refined, status] =
      refinement_after("/api/preview", [](const std::vector<double>& x) { return nlohmann::json{{"x", x}}.dump(); });
  EXPECT_EQ(status, 200);
  EXPECT_EQ(refined, "200 1");
}

TEST(PreviewRefinement, AMapLayerFromTheSameClientInterruptsTheRefinement) {
  // The page waits for its layer before refining again: the pass under way gives the layer the cores.
  const auto [refined, status] = refinement_after("/api/map", [](const std::vector<double>& x) {
    return nlohmann::json{{"layer", "variance"}, {"x", x}, {"rect", {x[0] - 1, x[0] + 1, x[1] - 1, x[1] + 1}},
                          {"size", {8, 8}}}
        .dump();
  });
  EXPECT_EQ(status, 200);
  EXPECT_EQ(refined, "200 1");
}

}  // namespace
}  // namespace matlas::server
