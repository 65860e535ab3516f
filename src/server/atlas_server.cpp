#include "server/atlas_server.h"

#include <atomic>
#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "server/api.h"
#include "server/http_error.h"
#include "server/web_root.h"

// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace matlas::server {

namespace {

const char* kNoUiPage = R"(<!doctype html><meta charset="utf-8"><title>matlas</title>
<body style="font-family:system-ui;background:#111;color:#ddd;padding:2em">
<h1>matlas</h1><p>The web UI is not built. Run <code>npm ci &amp;&amp; npm run build</code> in
<code>web/</code>, or point <code>--web-root</code> / <code>MATLAS_WEB_ROOT</code> at a built
<code>web/dist</code>. The JSON API is available under <code>/api/</code> (docs/API.md).</p></body>)";

void send_error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
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
  ServerOptions options;
  Api api;
  httplib::Server http;
  std::optional<std::filesystem::path> web_root;
  std::thread thread;
  int port = -1;

  Impl(const Model& model, std::shared_ptr<const PreviewSource> previews, ServerOptions o)
      : options(std::move(o)), api(model, std::move(previews), options) {
    web_root = find_web_root(options.web_root);
    configure();
  }

  void configure() {
    const int threads = std::max(2, options.threads);
    http.new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
    http.set_payload_max_length(options.max_upload_bytes);
    // Headers and body go out in separate writes: without TCP_NODELAY, Nagle + delayed ACK add
    // ~40 ms to every keep-alive response.
    http.set_tcp_nodelay(true);
    http.set_keep_alive_max_count(1000);
    http.set_keep_alive_timeout(5);
    http.set_read_timeout(10);
    http.set_write_timeout(10);

    http.Get("/api/model", [this](const httplib::Request&, httplib::Response& res) {
      guarded(res, [&] { return api.model_info(); });
    });
    auto post = [this](const std::string& path, Reply (Api::*method)(const std::string&)) {
      http.Post(path, [this, method](const httplib::Request& req, httplib::Response& res) {
        guarded(res, [&] { return (api.*method)(req.body); });
      });
    };
    post("/api/preview", &Api::preview);
    post("/api/weights", &Api::weights);
    post("/api/slice", &Api::slice);
    post("/api/lobe", &Api::lobe);
    post("/api/albedo", &Api::albedo);
    post("/api/map", &Api::map_layer);
    post("/api/export", &Api::export_merl);
    http.Post("/api/project", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        if (req.is_multipart_form_data()) {
          if (!req.has_file("file")) throw bad_request("the multipart upload has no field \"file\"");
          return api.project(req.get_file_value("file").content);
        }
        return api.project(req.body);
      });
    });
    http.Get(R"(/api/thumbnail/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        const int index = parse_int_text(req.matches[1], "material index", 0, 1 << 30);
        const int size = req.has_param("size") ? parse_int_text(req.get_param_value("size"), "size", 16, 512) : 128;
        return api.thumbnail(index, req.get_param_value("env"), req.get_param_value("object"), size);
      });
    });

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

    http.set_error_handler(httplib::Server::HandlerWithResponse(
        [](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      if (res.status == 413)
        send_error(res, 413, "the request body is too large");
      else if (res.status == 404)
        send_error(res, 404, "no such endpoint or file: " + req.path);
      else
        send_error(res, res.status, "request failed with status " + std::to_string(res.status));
      return httplib::Server::HandlerResponse::Handled;
    }));
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
      try {
        if (ep) std::rethrow_exception(ep);
        send_error(res, 500, "internal error");
      } catch (const std::exception& e) {
        send_error(res, 500, std::string("internal error: ") + e.what());
      } catch (...) {
        send_error(res, 500, "internal error");
      }
    });
    if (options.log) {
      // The logger runs on the thread that handled the request, right after it.
      static thread_local std::chrono::steady_clock::time_point started;
      http.set_pre_routing_handler([](const httplib::Request&, httplib::Response&) {
        started = std::chrono::steady_clock::now();
        return httplib::Server::HandlerResponse::Unhandled;
      });
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

}  // namespace matlas::server
