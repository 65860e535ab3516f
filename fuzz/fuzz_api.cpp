// Fuzz target: every endpoint handler of the API (server/api.h) on a small model built once. The
// first byte of the input picks the endpoint, the rest is its body. A handler may refuse (an
// HttpError or a matlas::Error); anything else (a crash, a sanitizer report, another exception)
// is a bug.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include <unistd.h>

#include "brdf/catalog.h"
#include "core/error.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "server/api.h"
#include "server/preview_source.h"

namespace {

using namespace matlas;
using namespace matlas::server;

/// Previews without a renderer: a constant image of the requested size.
class FlatPreviews final : public PreviewSource {
public:
  std::vector<std::string> environments() const override { return {"constant"}; }
  std::vector<std::string> objects() const override { return {"sphere"}; }
  std::string default_environment() const override { return "constant"; }
  std::string default_object() const override { return "sphere"; }
  int size() const override { return 32; }
  int drag_size() const override { return 16; }
  ToneMap tone() const override { return {}; }
  Image render(const Eigen::VectorXd& w, const std::string&, const std::string&, int size) const override {
    Image image(size, size);
    for (float& v : image.rgb) v = static_cast<float>(w.sum());
    return image;
  }
};

struct Fixture {
  std::filesystem::path dir;
  std::unique_ptr<Model> model;
  std::unique_ptr<Api> api;
  Fixture() {
    dir = std::filesystem::temp_directory_path() / ("matlas-fuzz-api-" + std::to_string(::getpid()));
    write_database(dir / "db", random_catalog(4, 7), null_progress(), MerlDims{4, 4, 8});
    BuildOptions o;
    o.dim = 2;
    build_model(MaterialSet::open({dir / "db"}), o, dir / "m.matlas");
    model = std::make_unique<Model>(Model::open(dir / "m.matlas"));
    ServerOptions so;
    so.queue_timeout = std::chrono::milliseconds(0);
    // Coarse .bsdf grids: the default ones take about 19 s per export under ASan here, near
    // libFuzzer's -timeout (scripts/fuzz.sh); the code paths are the same.
    so.bsdf_export.theta_i = 4;
    so.bsdf_export.vndf_resolution = 8;
    so.bsdf_export.rgb_resolution = 8;
    so.bsdf_export.sigma_resolution = 16;
    so.bsdf_export.ndf.nodes = 31;
    api = std::make_unique<Api>(*model, std::make_shared<FlatPreviews>(), so);
  }
  ~Fixture() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture f;
  if (size == 0) return 0;
  const std::string body(reinterpret_cast<const char*>(data) + 1, size - 1);
  Api& api = *f.api;
  try {
    switch (data[0] % 14) {
      case 0: api.weights(body); break;
      case 1: api.preview(body); break;
      case 2: api.slice(body); break;
      case 3: api.lobe(body); break;
      case 4: api.albedo(body); break;
      case 5: api.map_layer(body); break;
      case 6: api.export_file(body); break;
      case 7: api.project(body); break;
      case 8: api.thumbnail(static_cast<int>(body.size()) - 2, body, "sphere", 16 + static_cast<int>(body.size() % 64)); break;
      case 9: api.fit_samples(body, body.size() % 2 ? "1" : "0"); break;
      case 10: api.sample_plan(body, std::to_string(1 + body.size() % 8)); break;
      case 11: api.fit(body); break;
      case 12: api.fit_file(body); break;
      default: api.model_info(); break;
    }
  } catch (const Error&) {  // HttpError is a matlas::Error
  }
  return 0;
}
