#include "server/atlas_server.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "manifold/model.h"
#include "server/api.h"
#include "server/http_error.h"
#include "server/web_root.h"

// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include "server/guarded_http.h"

namespace matlas::server {

namespace {

const char* kNoUiPage = R"(<!doctype html><meta charset="utf-8"><title>matlas</title>
<body style="font-family:system-ui;background:#111;color:#ddd;padding:2em">
<h1>matlas</h1><p>The web UI is not built. Run <code>npm ci &amp;&amp; npm run build</code> in
<code>web/</code>, or point <code>--web-root</code> / <code>MATLAS_WEB_ROOT</code> at a built
<code>web/dist</code>. The JSON API is available under <code>/api/</code> (docs/API.md).</p></body>)";

/// Never throws for the message's content: bytes that are not UTF-8 (from a model's names, a
/// file's path) are replaced rather than thrown on (the JSON library's default), because this
/// runs in the error handlers too, outside the HTTP library's try/catch.
void send_error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", message}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  "application/json");
}

void send(httplib::Response& res, const Reply& reply) {
  res.status = reply.status;
  for (const auto& [k, v] : reply.headers) res.set_header(k, v);
  res.set_content(reply.body, reply.content_type);
}

/// Runs a handler, turning every exception into a JSON error reply.
template <class F>
void guarded(httplib::Response& res, F&& f) {
  try {
    send(res, f());
  } catch (const HttpError& e) {
    send_error(res, e.status(), e.what());
  } catch (const Error& e) {
    send_error(res, 400, e.what());
  } catch (const std::bad_alloc&) {
    send_error(res, 503, "out of memory");
  } catch (const std::exception& e) {
    send_error(res, 500, std::string("internal error: ") + e.what());
  }
}

}  // namespace

struct AtlasServer::Impl {
  /// What answers the API: a model, its previews and the Api over them, replaced as a whole on
  /// reload (requests in flight keep the one they started with).
  struct Served {
    std::shared_ptr<const Model> model;
    std::shared_ptr<const PreviewSource> previews;
    std::unique_ptr<Api> api;
    std::atomic<bool> broken{false};  ///< its file was modified in place: data untrustworthy
  };

  ServerOptions options;
  std::filesystem::path model_path;
  std::mutex served_mutex;
  std::shared_ptr<Served> served;
  GuardedHttpServer http;
  std::optional<std::filesystem::path> web_root;
  std::thread thread;
  int port = -1;

  // Model watch.
  std::atomic<long long> next_check_ms{0};
  std::atomic<bool> reloading{false};
  std::atomic<std::uint64_t> reloads{0};
  std::mutex status_mutex;
  std::string reload_error;                  ///< last failed reload, for the 503 message
  std::thread reload_thread;
  std::atomic<int> uploads{0};

  Impl(const Model& model, std::shared_ptr<const PreviewSource> previews, ServerOptions o)
      : options(std::move(o)), model_path(model.path()), http(limits(options)) {
    auto s = std::make_shared<Served>();
    s->model = std::shared_ptr<const Model>(&model, [](const Model*) {});  // owned by the caller
    s->previews = std::move(previews);
    s->api = std::make_unique<Api>(*s->model, s->previews, options);
    served = std::move(s);
    web_root = find_web_root(options.web_root);
    configure();
  }

  ~Impl() {
    if (reload_thread.joinable()) reload_thread.join();
  }

  static ConnectionLimits limits(const ServerOptions& o) {
    ConnectionLimits l;
    l.threads = std::max(2, o.threads);
    l.queue = std::max(0, o.queue);
    l.per_client = std::max(1, o.per_client);
    l.idle_timeout = o.idle_timeout;
    l.header_timeout = o.header_timeout;
    l.body_timeout = o.body_timeout;
    return l;
  }

  std::shared_ptr<Served> current() {
    std::lock_guard<std::mutex> lock(served_mutex);
    return served;
  }

  static long long now_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  /// At most every 200 ms: has the model file changed? Starts a reload if so.
  void check_model() {
    const long long now = now_ms();
    long long due = next_check_ms.load();
    if (now < due || !next_check_ms.compare_exchange_strong(due, now + 200)) return;
    const auto s = current();
    const Model::FileState state = s->model->file_state();
    if (state == Model::FileState::modified || s->model->mapping_faults() > 0) s->broken = true;
    if (state == Model::FileState::same || !options.reload || reloading.exchange(true)) return;
    if (reload_thread.joinable()) reload_thread.join();
    reload_thread = std::thread([this] {
      try {
        ServedModel m = options.reload(model_path);
        auto next = std::make_shared<Served>();
        next->model = std::move(m.model);
        next->previews = std::move(m.previews);
        next->api = std::make_unique<Api>(*next->model, next->previews, options);
        {
          std::lock_guard<std::mutex> lock(served_mutex);
          served = std::move(next);
        }
        ++reloads;
        std::lock_guard<std::mutex> lock(status_mutex);
        reload_error.clear();
      } catch (const std::exception& e) {
        // E.g. a copy still in progress: tried again at a later check (at most once a second).
        std::lock_guard<std::mutex> lock(status_mutex);
        reload_error = e.what();
        next_check_ms = now_ms() + 1000;
      }
      reloading = false;
    });
  }

  std::string unavailable_message() {
    std::string message = "the model file " + model_path.string() + " was modified while being served";
    std::lock_guard<std::mutex> lock(status_mutex);
    if (!options.reload) return message + "; restart the server to serve the new one";
    if (!reload_error.empty()) return message + "; it cannot be loaded yet: " + reload_error;
    return message + "; reloading, retry shortly";
  }

  /// Runs an API handler on the current model; a reply computed while the model's file was
  /// truncated under it (pages read as zeros) is replaced by 503.
  template <class F>
  void serve_api(httplib::Response& res, F&& f) {
    const auto s = current();
    if (s->broken) {
      res.set_header("Retry-After", "1");
      send_error(res, 503, unavailable_message());
      return;
    }
    const std::uint64_t faults = s->model->mapping_faults();
    guarded(res, [&] { return f(*s->api); });
    if (s->model->mapping_faults() != faults) {
      s->broken = true;
      res.set_header("Retry-After", "1");
      send_error(res, 503, unavailable_message());
    }
  }

  std::size_t body_limit(const httplib::Request& req) const {
    if (req.path == "/api/project") return options.max_upload_bytes + (64u << 10);
    if (req.path == "/api/fit-samples" || req.path == "/api/sample-plan") return kMaxSampleBody + (64u << 10);
    return kMaxJsonBody;
  }

  /// Before the body is read: its size limit, the multipart boundary, the upload slots.
  bool admit(const httplib::Request& req, httplib::Response& res) {
    const std::size_t limit = body_limit(req);
    GuardedHttpServer::begin_body(limit);
    long long length = -1;
    if (req.has_header("Content-Length")) {
      const std::string text = req.get_header_value("Content-Length");
      // Digits only: strtoull alone would read "-1" as 2^64 - 1 (a 413 instead of a 400).
      const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
      length = !digits ? -2 : text.size() > 18 ? (1ll << 62) : std::stoll(text);
    }
    if (length == -2) {
      send_error(res, 400, "invalid Content-Length header");
      GuardedHttpServer::close_after_response();
      return false;
    }
    if (length > static_cast<long long>(limit)) {
      send_error(res, 413, "the request body has " + std::to_string(length) + " bytes; " + req.path + " accepts at most " +
                               std::to_string(limit));
      GuardedHttpServer::close_after_response();
      return false;
    }
    const bool file_upload = req.path == "/api/project" || req.path == "/api/fit-samples" || req.path == "/api/sample-plan";
    if (file_upload && req.method == "POST") {
      const std::string type = req.get_header_value("Content-Type");
      if (type.rfind("multipart/form-data", 0) == 0 && type.find("boundary=") == std::string::npos) {
        // Read the body anyway (it is within the limit), so that the client gets this reply
        // rather than a connection reset.
        if (length < 0 || !GuardedHttpServer::discard_body(static_cast<std::size_t>(length)))
          GuardedHttpServer::close_after_response();
        send_error(res, 400, "the multipart upload has no boundary in its Content-Type "
                             "(expected multipart/form-data; boundary=...); or send the file as the raw body");
        return false;
      }
    }
    if (req.path == "/api/project" && req.method == "POST") {
      if (uploads.fetch_add(1) >= options.max_uploads) {
        uploads.fetch_sub(1);
        res.set_header("Retry-After", "1");
        send_error(res, 503, "the server is receiving " + std::to_string(options.max_uploads) +
                                 " uploads already; try again");
        GuardedHttpServer::close_after_response();
        return false;
      }
      upload_slot() = true;
    }
    if (req.path.rfind("/api/", 0) == 0) check_model();
    return true;
  }

  static bool& upload_slot() {
    thread_local bool held = false;
    return held;
  }

  void configure() {
    configure_connections();
    route_api();
    route_web_root();
    install_handlers();
  }

  /// Body limit, TCP_NODELAY, keep-alive, and the upload slot's release after every request.
  void configure_connections() {
    http.set_payload_max_length(options.max_upload_bytes + (64u << 10));
    // Headers and body go out in separate writes: without TCP_NODELAY, Nagle + delayed ACK add
    // ~40 ms to every keep-alive response.
    http.set_tcp_nodelay(true);
    // As many requests per connection as the connection loop serves (the Keep-Alive header says so).
    http.set_keep_alive_max_count(1000);
    http.after_request = [this] {
      if (upload_slot()) {
        upload_slot() = false;
        uploads.fetch_sub(1);
      }
    };
  }

  /// The JSON API's endpoints (docs/API.md), each answered by Api through serve_api.
  void route_api() {
    http.Get("/api/model", [this](const httplib::Request&, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.model_info(); });
    });
    http.Get("/api/interpolation", [this](const httplib::Request&, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.interpolation(); });
    });
    auto post = [this](const std::string& path, Reply (Api::*method)(const std::string&)) {
      http.Post(path, [this, method](const httplib::Request& req, httplib::Response& res) {
        serve_api(res, [&](Api& api) { return (api.*method)(req.body); });
      });
    };
    post("/api/preview", &Api::preview);
    post("/api/preview/refine", &Api::preview_refine);
    post("/api/gi/refine", &Api::gi_refine);
    post("/api/weights", &Api::weights);
    post("/api/slice", &Api::slice);
    post("/api/lobe", &Api::lobe);
    post("/api/albedo", &Api::albedo);
    post("/api/map", &Api::map_layer);
    post("/api/export", &Api::export_file);
    post("/api/fit", &Api::fit);
    post("/api/fit/file", &Api::fit_file);
    post("/api/realtime/lights", &Api::realtime_lights);
    post("/api/realtime/reference", &Api::realtime_reference);
    post("/api/realtime/reference/radiance", &Api::realtime_reference_radiance);
    http.Get("/api/realtime", [this](const httplib::Request&, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.realtime_info(); });
    });
    http.Get("/api/realtime/coefficients", [this](const httplib::Request&, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.realtime_coefficients(); });
    });
    http.Get(R"(/api/realtime/environment/([A-Za-z0-9_.-]+))", [this](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.realtime_environment(req.matches[1]); });
    });
    http.Get(R"(/api/realtime/mesh/([A-Za-z0-9_.-]+))", [this](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.realtime_mesh(req.matches[1]); });
    });
    http.Post("/api/project", [this](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) {
        if (req.is_multipart_form_data()) {
          if (!req.has_file("file")) throw bad_request("the multipart upload has no field \"file\"");
          return api.project(req.get_file_value("file").content);
        }
        return api.project(req.body);
      });
    });
    // Sample files: the raw body (CSV or JSON text), or a multipart form's field "file".
    auto upload_text = [](const httplib::Request& req) {
      if (!req.is_multipart_form_data()) return req.body;
      if (!req.has_file("file")) throw bad_request("the multipart upload has no field \"file\"");
      return req.get_file_value("file").content;
    };
    http.Post("/api/fit-samples", [this, upload_text](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.fit_samples(upload_text(req), req.get_param_value("robust")); });
    });
    http.Post("/api/sample-plan", [this, upload_text](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.sample_plan(upload_text(req), req.get_param_value("k")); });
    });
    http.Get("/api/preview/status", [this](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) { return api.preview_status(req.get_param_value("env"), req.get_param_value("object")); });
    });
    http.Get("/api/gi", [this](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) {
        return api.gi(req.get_param_value("scene"), req.get_param_value("x"), req.get_param_value("exposure"),
                      req.get_param_value("tone"));
      });
    });
    http.Get(R"(/api/thumbnail/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
      serve_api(res, [&](Api& api) {
        const int index = parse_int_text(req.matches[1], "material index", 0, 1 << 30);
        const int size = req.has_param("size") ? parse_int_text(req.get_param_value("size"), "size", 16, 512) : 128;
        return api.thumbnail(index, req.get_param_value("env"), req.get_param_value("object"), size);
      });
    });
  }

  /// The web UI's built files (content-hashed assets cached for good), or a page saying there is
  /// no UI.
  void route_web_root() {
    if (web_root) {
      http.set_mount_point("/", web_root->string());
      http.set_file_request_handler([](const httplib::Request& req, httplib::Response& res) {
        // Vite names built assets by content hash: cache them; always revalidate the page itself.
        if (req.path.rfind("/assets/", 0) == 0)
          res.set_header("Cache-Control", "public, max-age=31536000, immutable");
        else
          res.set_header("Cache-Control", "no-cache");
      });
    } else {
      http.Get("/", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(kNoUiPage, "text/html; charset=utf-8");
      });
    }
  }

  /// httplib compresses text and JSON replies with the best encoding the client accepts, brotli
  /// first, at brotli's slowest quality (11, fixed): 53 s of CPU for the 33 MB of GET
  /// /api/interpolation at n = 1000 and 0.9 s for the web UI's script, on every page load, where
  /// gzip takes 1.4 s and 20 ms for 20-30 % more bytes. So "br" is taken out of the request's
  /// Accept-Encoding before the reply is written: gzip is used. (httplib hands handlers a const
  /// Request; the object itself is the server's own, not const.)
  static void without_brotli(const httplib::Request& req) {
    auto& headers = const_cast<httplib::Request&>(req).headers;  // names compare case-insensitively
    const auto [first, last] = headers.equal_range("Accept-Encoding");
    for (auto it = first; it != last; ++it) it->second = accept_encoding_without(it->second, "br");
  }

  /// Error and exception handlers, admission before routing, and the request log.
  void install_handlers() {
    // The error and exception handlers run outside httplib's try/catch: nothing here may throw
    // (an exception would end the process), whatever the request's path holds (GET /%FF).
    http.set_error_handler(httplib::Server::HandlerWithResponse(
        [](const httplib::Request& req, httplib::Response& res) noexcept {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      try {
        if (res.status == 413)
          send_error(res, 413, "the request body is too large");
        else if (res.status == 404)
          send_error(res, 404, "no such endpoint or file: " + quoted_excerpt(req.path, 200));
        else
          send_error(res, res.status, "request failed with status " + std::to_string(res.status));
      } catch (...) {
        res.set_content(R"({"error":"request failed"})", "application/json");
      }
      return httplib::Server::HandlerResponse::Handled;
    }));
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) noexcept {
      try {
        try {
          if (ep) std::rethrow_exception(ep);
          send_error(res, 500, "internal error");
        } catch (const std::exception& e) {
          send_error(res, 500, std::string("internal error: ") + e.what());
        }
      } catch (...) {
        res.status = 500;
        res.set_content(R"({"error":"internal error"})", "application/json");
      }
    });
    // The logger runs on the thread that handled the request, right after it.
    static thread_local std::chrono::steady_clock::time_point started;
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      started = std::chrono::steady_clock::now();
      set_request_client(req.remote_addr);
      without_brotli(req);
      return admit(req, res) ? httplib::Server::HandlerResponse::Unhandled
                             : httplib::Server::HandlerResponse::Handled;
    });
    if (options.log) {
      http.set_logger([log = options.log](const httplib::Request& req, const httplib::Response& res) {
        log(req.method, req.path, res.status,
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
      });
    }
  }

  void bind() {
    if (options.port == 0) {
      port = http.bind_to_any_port(options.host);
    } else {
      port = http.bind_to_port(options.host, options.port) ? options.port : -1;
    }
    if (port < 0)
      throw Error("cannot listen on " + options.host + ":" + std::to_string(options.port) +
                  " (in use, or not a local address); choose another with --port");
  }
};

AtlasServer::AtlasServer(const Model& model, std::shared_ptr<const PreviewSource> previews,
                         ServerOptions options)
    : impl_(std::make_unique<Impl>(model, std::move(previews), std::move(options))) {}

AtlasServer::~AtlasServer() { stop(); }

int AtlasServer::start() {
  impl_->bind();
  auto stopped = std::make_shared<std::atomic<bool>>(false);
  impl_->thread = std::thread([this, stopped] {
    impl_->http.listen_after_bind();
    *stopped = true;
  });
  // listen_after_bind sets is_running once its accept loop starts.
  while (!impl_->http.is_running() && !*stopped) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (*stopped) throw Error("the server on " + url() + " stopped at once");
  return impl_->port;
}

void AtlasServer::run() {
  impl_->bind();
  impl_->http.listen_after_bind();
}

void AtlasServer::stop() {
  if (!impl_) return;
  impl_->http.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

int AtlasServer::port() const { return impl_->port; }

std::string AtlasServer::url() const {
  return "http://" + impl_->options.host + ":" + std::to_string(impl_->port) + "/";
}

const std::optional<std::filesystem::path>& AtlasServer::web_root() const { return impl_->web_root; }

ServerStats AtlasServer::stats() const {
  const ConnectionStats c = impl_->http.stats();
  return {c.accepted, c.refused_busy, c.refused_per_client, c.timed_out, c.over_budget, impl_->reloads.load()};
}

}  // namespace matlas::server
