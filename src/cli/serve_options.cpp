#include "cli/serve_options.h"

#include <memory>

#include "core/error.h"
#include "manifold/model.h"

namespace matlas::cli {

server::ServerOptions server_options(const std::string& host, int port, const std::string& web_root, bool log,
                                     const Io& io) {
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

}  // namespace matlas::cli
