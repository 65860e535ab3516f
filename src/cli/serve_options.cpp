#include "cli/serve_options.h"

#include <atomic>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "core/error.h"
#include "manifold/model.h"

namespace matlas::cli {

server::ServerOptions server_options(const std::string& host, int port, const std::string& web_root, bool log,
                                     const Io& io) {
  // From here on the server watches its model (503 and a reload when it is truncated) and keeps
  // writing its caches: the command's own check of its mapped inputs would refuse them.
  leave_mapped_inputs_to_the_server();
  server::ServerOptions so;
  so.host = host;
  so.port = port;
  so.web_root = web_root;
  if (log)
    so.log = [io](const std::string& method, const std::string& path, int status, double ms) {
      print(io.err, "%s %s %d %.1f ms\n", method.c_str(), path.c_str(), status, ms);
    };
  return so;
}

std::function<server::ServedModel(const std::filesystem::path&)> model_reloader(server::BasisPreviewOptions po,
                                                                                const Io& io) {
  return [po, io](const std::filesystem::path& path) {
    print(io.err, "matlas: %s changed on disk: loading it again\n", path.string().c_str());
    try {
      auto model = std::make_shared<const Model>(Model::open(path));
      auto previews = std::make_shared<server::BasisPreviews>(*model, po);
      previews->prepare_default();
      print(io.err, "matlas: now serving the new %s (%d materials, q = %d)\n", path.string().c_str(),
                   model->count(), model->dim());
      return server::ServedModel{model, previews};
    } catch (const Error& e) {
      print(io.err, "matlas: cannot load the changed model yet: %s\n", e.what());
      throw;
    }
  };
}

void note_missing_web_ui(const server::AtlasServer& srv, const Io& io) {
  if (!srv.web_root())
    print(io.err, "note: the web UI is not built (run `npm ci && npm run build` in web/); serving the API only\n");
}

namespace {

bool parse_size(const std::string& text, int* width, int* height) {
  int w = 0, h = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 8 || h < 8 || w > 4096 || h > 4096) return false;
  if (width) *width = w;
  if (height) *height = h;
  return true;
}

}  // namespace

void add_gi_serve_options(CLI::App& cmd, GiServeArgs& a) {
  cmd.add_option("--gi-basis", a.bases, "GI bases (from matlas gi-basis) for the scene view, served as they are")
      ->check(CLI::ExistingFile);
  cmd.add_option("--gi-scenes", a.scenes, "Scenes of the scene view traced on demand and kept beside the model "
                                          "(floor, box or .json files, comma-separated; none: only --gi-basis)")
      ->capture_default_str();
  cmd.add_option("--gi-object", a.object, "The measured object of the scenes traced on demand")->capture_default_str();
  cmd.add_option("--gi-size", a.size, "Image size of the scenes traced on demand, WIDTHxHEIGHT")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) {
            return parse_size(text, nullptr, nullptr) ? std::string()
                                                      : "must be WIDTHxHEIGHT with sides in [8, 4096], got " + text;
          },
          "WIDTHxHEIGHT"));
  cmd.add_option("--gi-spp", a.spp, "Paths per pixel of the scenes traced on demand")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  cmd.add_option("--gi-refine-width", a.refine_width,
                 "Width of the scene view refined while the pointer rests (a direct trace of the point, at the "
                 "basis's aspect)")
      ->check(CLI::Range(8, 4096))
      ->capture_default_str();
  cmd.add_option("--gi-cache", a.cache, "Folder of the scenes traced on demand (default: MODEL.gi beside the model)");
}

std::function<std::shared_ptr<const server::GiScenes>(const Model&)> gi_scenes_factory(const GiServeArgs& a,
                                                                                      const Io& io) {
  server::GiSceneOptions o;
  for (const auto& b : a.bases) o.bases.emplace_back(b);
  o.scenes.clear();
  if (a.scenes != "none") {
    std::size_t begin = 0;
    for (;;) {
      const std::size_t comma = a.scenes.find(',', begin);
      if (std::string s = a.scenes.substr(begin, comma - begin); !s.empty()) o.scenes.push_back(s);
      if (comma == std::string::npos) break;
      begin = comma + 1;
    }
  }
  if (o.bases.empty() && o.scenes.empty()) return {};
  o.object = a.object;
  int w = 0, h = 0;
  if (!parse_size(a.size, &w, &h)) throw Error("--gi-size must be WIDTHxHEIGHT, got " + a.size);
  o.trace.width = w;
  o.trace.height = h;
  o.trace.spp = a.spp;
  o.refine_width = a.refine_width;
  o.cache_dir = a.cache;
  auto calls = std::make_shared<std::atomic<int>>(0);
  return [o, io, calls](const Model& model) -> std::shared_ptr<const server::GiScenes> {
    const bool first = calls->fetch_add(1) == 0;
    try {
      return std::make_shared<const server::GiScenes>(model, o);
    } catch (const Error& e) {
      if (first || o.bases.empty()) throw;  // at start-up a bad --gi-basis is an error
      print(io.err, "matlas: scene view without --gi-basis: %s\n", e.what());
      server::GiSceneOptions without = o;
      without.bases.clear();
      return std::make_shared<const server::GiScenes>(model, without);
    }
  };
}

}  // namespace matlas::cli
