#pragma once
// What `matlas serve` and `matlas demo` share: server options from their common flags, and the
// notice printed when the web UI has not been built.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/print.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "server/gi_scenes.h"

namespace matlas::cli {

/// Options for host, port and web root; with `log`, one line per request on io.err (`io` must
/// outlive the server). Calls leave_mapped_inputs_to_the_server() (cli/commands.h): the
/// command serves from then on.
server::ServerOptions server_options(const std::string& host, int port, const std::string& web_root, bool log,
                                     const Io& io);

/// The reload callback of `serve` and `demo`: opens the model again and prepares its default
/// previews (bases cached as for the first), saying so on io.err.
std::function<server::ServedModel(const std::filesystem::path&)> model_reloader(server::BasisPreviewOptions previews,
                                                                                const Io& io);

/// The scene view's flags (docs/GI.md): GI bases to serve and built-in scenes to trace on demand.
struct GiServeArgs {
  std::vector<std::string> bases;     ///< --gi-basis FILE...
  std::string scenes = "floor,box";   ///< --gi-scenes: traced on demand; "none": only the given bases
  std::string object = "sphere";      ///< --gi-object
  std::string size = "256x192";       ///< --gi-size WxH (the basis composed while dragging)
  int spp = 16;                       ///< --gi-spp
  int refine_width = 512;             ///< --gi-refine-width (the view refined at rest)
  std::string cache;                  ///< --gi-cache; empty: beside the model (MODEL.gi/)
};
void add_gi_serve_options(CLI::App& cmd, GiServeArgs& a);

/// ServerOptions::gi_scenes from the flags: the given bases are checked when the server starts
/// (matlas::Error naming a bad file); after a reload, bases of the old model are left out with a
/// note on io.err. An empty function when there are neither bases nor scenes.
std::function<std::shared_ptr<const server::GiScenes>(const Model&)> gi_scenes_factory(const GiServeArgs& a,
                                                                                      const Io& io);

/// Says on io.err that only the API is served when the server found no built web UI.
void note_missing_web_ui(const server::AtlasServer& srv, const Io& io);

}  // namespace matlas::cli
