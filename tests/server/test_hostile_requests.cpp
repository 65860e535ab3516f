// Hostile requests, second round (issue 28): paths and query strings that are not UTF-8, integers
// under a lower bound, a negative Content-Length, a NUL inside a JSON body, long values echoed in
// errors, and one client flooding the heavy slot from its own address (127.0.0.2, 127.0.0.3, ...
// are all loopback).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "brdf/catalog.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "support/temp_dir.h"

namespace matlas::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct HttpReply {
  int status = 0;
  std::string body;
};

/// One HTTP/1.1 request on a fresh connection from the loopback address `from`; the whole reply.
HttpReply raw_request(int port, const std::string& request, const char* from = "127.0.0.1") {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  ::inet_pton(AF_INET, from, &local.sin_addr);
  ::bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  HttpReply reply;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return reply;
  }
  timeval tv{120, 0};  // as long as the fairness test's queue may take on a loaded machine
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string out;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  if (out.rfind("HTTP/1.1 ", 0) == 0) reply.status = std::stoi(out.substr(9, 3));
  if (const auto end = out.find("\r\n\r\n"); end != std::string::npos) reply.body = out.substr(end + 4);
  return reply;
}

std::string get(const std::string& target) {
  return "GET " + target + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
}

std::string post(const std::string& target, const std::string& body, const std::string& length = "") {
  return "POST " + target + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Type: application/json\r\n" +
         "Content-Length: " + (length.empty() ? std::to_string(body.size()) : length) + "\r\n\r\n" + body;
}

class HostileRequests : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-hostile");
    write_database(dir_->path() / "db", random_catalog(5, 31), null_progress(), MerlDims{8, 8, 16});
    BuildOptions options;
    options.dim = 2;
    build_model(MaterialSet::open({dir_->path() / "db"}), options, dir_->path() / "a.matlas");
  }
  static void TearDownTestSuite() { delete dir_; }

  struct Live {
    std::unique_ptr<Model> model;
    std::shared_ptr<BasisPreviews> previews;
    std::unique_ptr<AtlasServer> server;
    explicit Live(ServerOptions so = {}) {
      model = std::make_unique<Model>(Model::open(dir_->path() / "a.matlas"));
      BasisPreviewOptions po;
      po.environments = {"constant"};
      po.objects = {"sphere"};
      po.size = 32;
      po.spp = 1;
      po.cache_dir = dir_->path() / "bases";
      previews = std::make_shared<BasisPreviews>(*model, po);
      previews->prepare_default();
      so.port = 0;
      server = std::make_unique<AtlasServer>(*model, previews, so);
      server->start();
    }
    int port() const { return server->port(); }
    std::string x() const { return json{model->latent()(0, 0), model->latent()(0, 1)}.dump(); }
    /// The server still answers.
    bool alive() const {
      return raw_request(port(), post("/api/weights", "{\"x\":" + x() + "}")).status == 200;
    }
  };

  static inline test::TempDir* dir_ = nullptr;
};

// ---- 1. Paths that are not UTF-8 get 404, and the server lives on
TEST_F(HostileRequests, PathsThatAreNotUtf8Get404NotACrash) {
  Live live;
  for (const std::string path : {"/%FF", "/api/realtime/mesh/%FF", "/%C0%AF", "/%ED%A0%80", "/a%80b"}) {
    const HttpReply r = raw_request(live.port(), get(path));
    EXPECT_EQ(r.status, 404) << path << ": " << r.body;
    const json j = json::parse(r.body);  // valid JSON (UTF-8) whatever the path held
    EXPECT_NE(j["error"].get<std::string>().find("\\x"), std::string::npos) << r.body;
    ASSERT_TRUE(live.alive()) << "the server died on GET " << path;
  }
}

TEST_F(HostileRequests, QueryStringsThatAreNotUtf8Get400) {
  Live live;
  for (const std::string target : {"/api/thumbnail/0?size=%FF", "/api/thumbnail/0?env=%FF%FE", "/api/gi?x=%FF"}) {
    const HttpReply r = raw_request(live.port(), get(target));
    EXPECT_GE(r.status, 400) << target;
    EXPECT_LT(r.status, 500) << target << ": " << r.body;
    EXPECT_NO_THROW(json::parse(r.body)) << r.body;
  }
  ASSERT_TRUE(live.alive());
}

// ---- 10. Lower bounds hold for non-negative integers (stored unsigned by the JSON library)
TEST_F(HostileRequests, IntegersUnderTheLowerBoundAreRefused) {
  Live live;
  const std::string x = live.x();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/api/preview", "{\"x\":" + x + ",\"size\":1}"},
      {"/api/preview", "{\"x\":" + x + ",\"size\":15}"},
      {"/api/lobe", "{\"x\":" + x + ",\"samples\":0}"},
      {"/api/lobe", "{\"x\":" + x + ",\"samples\":7}"},
      {"/api/map", "{\"layer\":\"albedo\",\"x\":" + x + ",\"rect\":[0,1,0,1],\"size\":[1,3]}"},
      {"/api/realtime/reference", "{\"x\":" + x + ",\"size\":15}"}};
  for (const auto& [path, body] : cases) {
    const HttpReply r = raw_request(live.port(), post(path, body));
    EXPECT_EQ(r.status, 400) << path << " " << body << ": " << r.body;
    EXPECT_NE(r.body.find("is outside ["), std::string::npos) << r.body;
  }
  // At the bound: accepted.
  EXPECT_EQ(raw_request(live.port(), post("/api/lobe", "{\"x\":" + x + ",\"samples\":8}")).status, 200);
}

// ---- 11. Content-Length, NUL bytes, long values
TEST_F(HostileRequests, NegativeContentLengthIs400) {
  Live live;
  for (const std::string length : {"-1", "+5", "0x10", "1e3", "12a"}) {
    const HttpReply r = raw_request(live.port(), post("/api/weights", "{}", length));
    EXPECT_EQ(r.status, 400) << "Content-Length: " << length << ": " << r.body;
  }
  ASSERT_TRUE(live.alive());
}

TEST_F(HostileRequests, ABodyWithANulIsRefused) {
  Live live;
  std::string body = "{\"x\":" + live.x() + "}";
  body += std::string(1, '\0') + "garbage";
  const HttpReply r = raw_request(live.port(), post("/api/weights", body));
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_NE(r.body.find("NUL"), std::string::npos) << r.body;
}

TEST_F(HostileRequests, LongValuesAreNotEchoed) {
  Live live;
  const std::string long_value(5000, 'q');
  const std::vector<std::string> requests = {
      post("/api/preview", "{\"x\":" + live.x() + ",\"env\":\"" + long_value + "\"}"),
      get("/api/thumbnail/0?size=" + long_value),
      get("/api/realtime/environment/" + long_value), get("/nothing/" + long_value)};
  for (const auto& request : requests) {
    const HttpReply r = raw_request(live.port(), request);
    EXPECT_GE(r.status, 400);
    EXPECT_LT(r.body.size(), 600u) << r.body.substr(0, 200);
    EXPECT_NE(r.body.find(" bytes)"), std::string::npos) << r.body.substr(0, 300);
  }
}

// ---- 12. Sample files (POST /api/fit-samples, /api/sample-plan): whatever the upload holds, a
// 4xx with a JSON message, and the server lives on
TEST_F(HostileRequests, HostileSampleFilesGet4xx) {
  Live live;
  const std::string header = "theta_i,phi_i,theta_o,phi_o,r,g,b\n";
  std::string wide = header;
  for (int i = 0; i < 50000; ++i) wide += "1,";
  const std::vector<std::string> bodies = {
      std::string(200000, '[') + std::string(200000, ']'),
      "{\"samples\":" + std::string(5000, '[') + "}",
      header + std::string("10,0,10,0,1,1,1") + std::string(1, '\0') + "\n",
      header + "10,0,10,0,\xff\xfe,1,1\n",
      header + "1e999,0,10,0,1,1,1\n",
      header + "10,0,10,0,-1,1,1\n",
      header + "nan,0,10,0,1,1,1\n",
      wide,
      std::string(300000, ',') + "\n",
      "theta_i\n" + std::string(1000, '\n'),
      "{\"samples\":[{\"wi\":[0,0,1],\"wo\":\"x\",\"rgb\":[1,1,1]}]}",
      "{\"samples\":[{\"wi\":[0,0,1],\"wo\":[0,0,1],\"rgb\":[1e308,1e308,1e308]}]}"};
  for (const std::string path : {"/api/fit-samples", "/api/sample-plan?k=3"}) {
    for (const auto& body : bodies) {
      const HttpReply r = raw_request(live.port(), post(path, body));
      // A plan skips invalid rows and plans afresh (200); a fit needs valid samples.
      EXPECT_GE(r.status, path == std::string("/api/fit-samples") ? 400 : 200) << path << " " << body.substr(0, 60);
      EXPECT_LT(r.status, 500) << path << " " << body.substr(0, 60) << ": " << r.body;
      EXPECT_NO_THROW(json::parse(r.body)) << r.body.substr(0, 200);
      ASSERT_TRUE(live.alive()) << "the server died on " << path << " " << body.substr(0, 60);
    }
  }
  for (const std::string k : {"-1", "101", "99999999999999999999", "%FF", "1.5"})
    EXPECT_EQ(raw_request(live.port(), post("/api/sample-plan?k=" + k, "")).status, 400) << k;
  const HttpReply multipart = raw_request(
      live.port(), "POST /api/fit-samples HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Type: multipart/form-data\r\n"
                   "Content-Length: 4\r\n\r\nabcd");
  EXPECT_EQ(multipart.status, 400) << multipart.body;
  ASSERT_TRUE(live.alive());
}

// ---- 11. Fairness: one address flooding the heavy slot does not starve another
TEST_F(HostileRequests, AFloodFromOneAddressDoesNotStarveAnother) {
  ServerOptions so;
  so.heavy_slots = 1;
  so.waiting_per_client = 3;
  so.queue_timeout = std::chrono::milliseconds(120000);  // no timeouts here, however loaded the machine
  Live live(so);
  // CPU references of the real-time view at 256 x 256: heavy requests of a second or more each (at
  // 128 x 128 an idle 2-core machine finished one before all eight had arrived, admitting a fifth;
  // at 512 x 512 a loaded one kept the last queued past a 30 s read timeout).
  const std::string heavy = post("/api/realtime/reference", "{\"x\":" + live.x() + ",\"size\":256}");
  std::mutex m;
  std::vector<std::string> done;  // who, in order of completion
  std::atomic<int> flood_ok{0}, flood_refused{0};
  std::vector<std::thread> flood;
  for (int i = 0; i < 8; ++i)
    flood.emplace_back([&] {
      const HttpReply r = raw_request(live.port(), heavy, "127.0.0.2");
      if (r.status == 503) {
        ++flood_refused;
        return;
      }
      if (r.status == 200) ++flood_ok;
      std::lock_guard lock(m);
      done.emplace_back("flood");
    });
  // The flooder holds the slot and may queue 3 more: the other 4 are refused at once, before
  // anything else finishes.
  const auto wait_until = Clock::now() + std::chrono::seconds(60);
  while (flood_refused.load() < 4 && Clock::now() < wait_until) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::size_t done_before = 0;
  {
    std::lock_guard lock(m);
    done_before = done.size();
  }
  const HttpReply polite = raw_request(live.port(), heavy, "127.0.0.3");
  std::size_t flood_done_meanwhile = 0;
  {
    std::lock_guard lock(m);
    flood_done_meanwhile = done.size() - done_before;
  }
  for (auto& t : flood) t.join();
  EXPECT_EQ(polite.status, 200) << polite.body;
  EXPECT_EQ(flood_ok.load(), 4);
  EXPECT_EQ(flood_refused.load(), 4);
  // The polite client is served right after the request running when it arrived, before the
  // flooder's queued ones: first come, first served would have served those 3 first.
  EXPECT_EQ(done_before, 0u) << "the flood's first request finished before the polite one was sent";
  EXPECT_LE(flood_done_meanwhile, 1u);
}

}  // namespace
}  // namespace matlas::server
