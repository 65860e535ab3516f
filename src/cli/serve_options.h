#pragma once
// What `matlas serve` and `matlas demo` share: server options from their common flags, and the
// notice printed when the web UI has not been built.
#include <filesystem>
#include <functional>
#include <string>

#include "cli/print.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"

namespace matlas::cli {

/// Options for host, port and web root; with `log`, one line per request on io.err (`io` must
/// outlive the server).
server::ServerOptions server_options(const std::string& host, int port, const std::string& web_root, bool log,
                                     const Io& io);

/// The reload callback of `serve` and `demo`: opens the model again and prepares its default
/// previews (bases cached as for the first), saying so on io.err.
std::function<server::ServedModel(const std::filesystem::path&)> model_reloader(server::BasisPreviewOptions previews,
                                                                                const Io& io);

/// Says on io.err that only the API is served when the server found no built web UI.
void note_missing_web_ui(const server::AtlasServer& srv, const Io& io);

}  // namespace matlas::cli
