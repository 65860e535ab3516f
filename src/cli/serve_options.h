#pragma once
// What `matlas serve` and `matlas demo` share: server options from their common flags, and the
// notice printed when the web UI has not been built.
#include <filesystem>
#include <functional>
#include <string>

#include "server/atlas_server.h"
#include "server/basis_previews.h"

namespace matlas::cli {

/// Options for host, port and web root; with `log`, one stderr line per request.
server::ServerOptions server_options(const std::string& host, int port, const std::string& web_root, bool log);

/// The reload callback of `serve` and `demo`: opens the model again and prepares its default
/// previews (bases cached as for the first), saying so on stderr.
std::function<server::ServedModel(const std::filesystem::path&)> model_reloader(server::BasisPreviewOptions previews);

/// Says on stderr that only the API is served when the server found no built web UI.
void note_missing_web_ui(const server::AtlasServer& srv);

}  // namespace matlas::cli
