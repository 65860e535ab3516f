// The server's interpolation mode (ServerOptions::interpolation, `matlas serve --interpolation`):
// every query of one server uses it, and two servers of different modes share one Model at once.
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "manifold/model.h"
#include "server/atlas_server.h"
#include "small_model.h"
#include "support/temp_dir.h"

// Last: httplib.h defines a `_res` macro (from <resolv.h>) that breaks Eigen headers after it.
#include <httplib.h>

namespace matlas::server {
namespace {

using nlohmann::json;

json get_json(const AtlasServer& s, const char* path) {
  httplib::Client c("127.0.0.1", s.port());
  auto r = c.Get(path);
  EXPECT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  return json::parse(r->body);
}

Eigen::VectorXd served_weights(const AtlasServer& s, const Eigen::VectorXd& x) {
  httplib::Client c("127.0.0.1", s.port());
  auto r = c.Post("/api/weights", json{{"x", std::vector<double>(x.data(), x.data() + x.size())}}.dump(),
                  "application/json");
  EXPECT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  const auto w = json::parse(r->body).at("weights").get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
}

TEST(ServerMode, EachServerAnswersInItsOwnModeOverOneModel) {
  test::TempDir dir("matlas-server-mode");
  const Model model = test::build_small_model(dir.path(), 6, 5);
  ASSERT_EQ(model.interpolation(), Interpolation::convex);  // a default build
  const auto previews = test::sphere_previews(model, 24, 1);
  ServerOptions so;
  so.port = 0;
  so.threads = 8;
  AtlasServer own(model, previews, so);  // the model's mode
  so.interpolation = Interpolation::gp;
  AtlasServer gp(model, previews, so);
  own.start();
  gp.start();

  EXPECT_EQ(get_json(own, "/api/model").at("interpolation"), "convex");
  EXPECT_EQ(get_json(gp, "/api/model").at("interpolation"), "gp");
  EXPECT_EQ(get_json(gp, "/api/interpolation").at("mode"), "gp");
  // A point off the data, where the two modes differ.
  const Eigen::VectorXd x = model.latent_max() + 0.2 * (model.latent_max() - model.latent_min());
  const Eigen::VectorXd convex_w = model.weights(x, Interpolation::convex), gp_w = model.weights(x, Interpolation::gp);
  ASSERT_GT((convex_w - gp_w).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((served_weights(own, x) - convex_w).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((served_weights(gp, x) - gp_w).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(model.interpolation(), Interpolation::convex);  // the shared model is unchanged
}

}  // namespace
}  // namespace matlas::server
