#pragma once
// AtlasServer: the material browser's HTTP server (cpp-httplib): the JSON API of docs/API.md and
// the built web UI (web/dist, found by find_web_root) as static files.
//
// The model file is watched: if it is replaced (renamed over), the server keeps answering from the
// old one while `reload` prepares the new one, then switches; if it is modified or truncated in
// place (the mapped data is no longer trustworthy), model requests get 503 until the reload.
//
// Robustness: connections are served by a bounded thread pool with deadlines and per-client
// limits (server/guarded_http.h); heavy work (previews and panels on
// one side, whole tables, projections and map layers on the other) passes through first-come,
// first-served ComputeGates sized to the machine, so a burst of requests queues instead of
// oversubscribing the CPU, and a request that cannot get a slot in time gets 503. Bad requests get
// 4xx with a JSON {"error": message}; an exception never escapes a handler.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "formats/rgl_bsdf_writer.h"
#include "manifold/interpolation.h"

namespace matlas {
class Model;
}

namespace matlas::server {

class PreviewSource;
class GiScenes;

/// A model and its previews, as a reload gives them (see ServerOptions::reload).
struct ServedModel {
  std::shared_ptr<const Model> model;
  std::shared_ptr<const PreviewSource> previews;
};

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;                          ///< 0: an ephemeral port (see AtlasServer::port())
  std::filesystem::path web_root;           ///< empty: find_web_root(); none found: API only
  int threads = 256;                        ///< connection threads (each open connection holds one)
  int queue = 512;                          ///< connections waiting for a thread (503 beyond)
  int per_client = 64;                      ///< simultaneous connections per client address (503 beyond)
  std::chrono::milliseconds idle_timeout{5000};    ///< an idle connection is closed after this
  std::chrono::milliseconds header_timeout{5000};  ///< request line + headers, from their first byte
  std::chrono::milliseconds body_timeout{60000};   ///< the request body, after the headers
  int max_uploads = 4;                      ///< uploads (POST /api/project) received at once
  int compute_slots = 0;                    ///< concurrent preview/panel computations; 0: cores
  int heavy_slots = 1;                      ///< concurrent exports, projections, map layers
  std::chrono::milliseconds queue_timeout{15000};  ///< longest wait for a slot before 503
  /// Requests of one client (address) waiting for the same kind of slot; one more gets 503 at
  /// once. The slots go to the waiting client that used them least lately (server/compute_gate.h).
  int waiting_per_client = 4;
  std::size_t max_upload_bytes = 64u << 20;        ///< larger uploads get 413 (other requests: 64 KiB)
  double domain_margin = 1.0;               ///< allowed x: data box enlarged by this x extent
  /// The interpolation mode of every query the server answers (weights, previews, panels, map
  /// layers, fits, projections), kept across reloads; empty: each model's own mode.
  std::optional<Interpolation> interpolation;
  std::size_t cache_entries = 512;          ///< LRU of encoded previews
  /// The grids of POST /api/export's .bsdf files (the defaults: what `matlas export -o X.bsdf`
  /// writes; the API fuzz target uses coarse ones so that one export stays well under a second).
  /// The description is set per request.
  RglExportOptions bsdf_export;
  /// Called after each request with (method, path, status, milliseconds) (e.g. an access log).
  std::function<void(const std::string&, const std::string&, int, double)> log;
  /// Opens the model file again (and prepares its previews) after it changed on disk. Without it,
  /// a changed model file is reported (503) until the server is restarted.
  std::function<ServedModel(const std::filesystem::path&)> reload;
  /// The scene view's GI bases of a model (server/gi_scenes.h), called for the served model and
  /// after each reload. Without it, GET /api/gi answers 404.
  std::function<std::shared_ptr<const GiScenes>(const Model&)> gi_scenes;
};

/// Counters of the connection layer (server/guarded_http.h) and of model reloads.
struct ServerStats {
  std::uint64_t connections = 0, refused_busy = 0, refused_per_client = 0, timed_out = 0, over_budget = 0;
  std::uint64_t reloads = 0;
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
  ServerStats stats() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace matlas::server
