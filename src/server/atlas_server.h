#pragma once
// AtlasServer: the material browser's HTTP server (cpp-httplib): the JSON API of docs/API.md and
// the built web UI (web/dist, found by find_web_root) as static files.
//
// Robustness: connections are served by a fixed thread pool; heavy work (previews and panels on
// one side, whole tables, projections and map layers on the other) passes through first-come,
// first-served ComputeGates sized to the machine, so a burst of requests queues instead of
// oversubscribing the CPU, and a request that cannot get a slot in time gets 503. Bad requests get
// 4xx with a JSON {"error": message}; an exception never escapes a handler.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace matlas {
class Model;
}

namespace matlas::server {

class PreviewSource;

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;                          ///< 0: an ephemeral port (see AtlasServer::port())
  std::filesystem::path web_root;           ///< empty: find_web_root(); none found: API only
  int threads = 64;                         ///< connection threads (keep-alive clients hold one)
  int compute_slots = 0;                    ///< concurrent preview/panel computations; 0: cores
  int heavy_slots = 1;                      ///< concurrent exports, projections, map layers
  std::chrono::milliseconds queue_timeout{15000};  ///< longest wait for a slot before 503
  std::size_t max_upload_bytes = 64u << 20;        ///< larger bodies get 413
  double domain_margin = 1.0;               ///< allowed x: data box enlarged by this x extent
  std::size_t cache_entries = 512;          ///< LRU of encoded previews
  /// Called after each request with (method, path, status, milliseconds) (e.g. an access log).
  std::function<void(const std::string&, const std::string&, int, double)> log;
};

class AtlasServer {
public:
  /// `model` and `previews` must outlive the server.
  AtlasServer(const Model& model, std::shared_ptr<const PreviewSource> previews, ServerOptions options);
  ~AtlasServer();
  AtlasServer(const AtlasServer&) = delete;
  AtlasServer& operator=(const AtlasServer&) = delete;

  /// Binds and serves on a background thread; returns the port. Throws matlas::Error naming
  /// host:port if it cannot bind.
  int start();
  /// Binds and serves on the calling thread until stop() (from another thread or a signal).
  void run();
  void stop();

  int port() const;
  /// http://host:port/
  std::string url() const;
  /// The static files served, if any.
  const std::optional<std::filesystem::path>& web_root() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace matlas::server
