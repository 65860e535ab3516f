// matlas serve MODEL: the material browser (web UI + JSON API, docs/API.md) for a built model.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/print.h"
#include "cli/serve_options.h"
#include "core/error.h"
#include "core/progress.h"
#include "manifold/model.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "server/serving.h"

namespace matlas::cli {

namespace {

struct ServeArgs {
  std::string model;
  std::string host = "127.0.0.1";
  int port = 8080;
  std::string web_root;
  std::string cache;
  std::string env = "studio";
  int size = 256;
  int spp = 32;
  int threads = 256;
  bool log = false;
  std::string interpolation;  ///< empty: the model's own mode
  GiServeArgs gi;
};

void run_serve(const ServeArgs& a, const Io& io) {
  server::block_stop_signals();  // before any thread starts: every thread inherits the mask
  const Model model = Model::open(a.model);
  std::optional<Interpolation> mode;
  if (!a.interpolation.empty()) mode = interpolation_from_string(a.interpolation);
  server::BasisPreviewOptions po;
  po.default_environment = a.env;
  po.size = a.size;
  po.spp = a.spp;
  // The same cache folder as `matlas demo --cache`; serve uses only its bases/ (docs/WEB.md).
  po.cache_dir = (a.cache.empty() ? server::default_cache_dir() : std::filesystem::path(a.cache)) / "bases";
  auto previews = std::make_shared<server::BasisPreviews>(model, po);
  {
    TerminalProgress progress;
    print(io.err, "preparing previews (%s on %s, %dx%d, %d spp; cached in %s)\n",
                 previews->default_environment().c_str(), previews->default_object().c_str(), a.size, a.size, a.spp,
                 po.cache_dir.string().c_str());
    previews->prepare_default(progress);
  }
  server::ServerOptions so = server_options(a.host, a.port, a.web_root, a.log, io);
  so.threads = a.threads;
  so.interpolation = mode;
  so.reload = model_reloader(po, io);
  so.gi_scenes = gi_scenes_factory(a.gi, io);
  server::AtlasServer srv(model, previews, so);
  note_missing_web_ui(srv, io);
  server::serve_until_signal(srv, [&](const std::string& url) {
    print(io.out, "matlas: serving %s (%d materials, q = %d, %s interpolation) at %s\n",
                model.path().filename().string().c_str(), model.count(), model.dim(),
                to_string(mode.value_or(model.interpolation())), url.c_str());
    io.out.flush();
  });
}

void add_serve_command(CLI::App& app, const Io& io) {
  auto a = std::make_shared<ServeArgs>();
  auto* cmd = app.add_subcommand("serve", "Serve the material browser (web UI and JSON API) for a model");
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("--interpolation", a->interpolation,
                  "Override the model's interpolation mode: convex (non-negative weights summing to 1) or gp (the "
                  "paper's GP weights)");
  cmd->add_option("--host", a->host, "Address to listen on")->capture_default_str();
  cmd->add_option("--port", a->port, "Port (0: any free port)")->check(CLI::Range(0, 65535))->capture_default_str();
  cmd->add_option("--web-root", a->web_root, "Built web UI folder (default: $MATLAS_WEB_ROOT, or web/dist near the executable)");
  cmd->add_option("--cache", a->cache, "Cache folder, as for demo; image bases are kept in its bases/ (default: $MATLAS_CACHE or ~/.cache/matlas)");
  cmd->add_option("--env", a->env, "Default environment map of the previews")->capture_default_str();
  cmd->add_option("--size", a->size, "Preview size in pixels")->check(CLI::Range(32, 1024))->capture_default_str();
  cmd->add_option("--spp", a->spp, "Samples per pixel of the preview bases")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--threads", a->threads, "Connection threads (each open connection holds one)")->check(CLI::Range(2, 4096))->capture_default_str();
  cmd->add_flag("--log", a->log, "Print one line per request on stderr");
  add_gi_serve_options(*cmd, a->gi);
  cmd->callback([io, a] { run_serve(*a, io); });
}

}  // namespace

MATLAS_COMMAND(90, add_serve_command);

}  // namespace matlas::cli
