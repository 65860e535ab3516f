#include "cli/serve_options.h"

#include <cstdio>

namespace matlas::cli {

server::ServerOptions server_options(const std::string& host, int port, const std::string& web_root, bool log) {
  server::ServerOptions so;
  so.host = host;
  so.port = port;
  so.web_root = web_root;
  if (log)
    so.log = [](const std::string& method, const std::string& path, int status, double ms) {
      std::fprintf(stderr, "%s %s %d %.1f ms\n", method.c_str(), path.c_str(), status, ms);
    };
  return so;
}

void note_missing_web_ui(const server::AtlasServer& srv) {
  if (!srv.web_root())
    std::fprintf(stderr, "note: the web UI is not built (run `npm ci && npm run build` in web/); serving the API only\n");
}

}  // namespace matlas::cli
