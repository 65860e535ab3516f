#include "atlas/model_basis.h"

#include <cstdint>
#include <cstdio>
#include <map>
#include <vector>

#include "atlas/model_material.h"
#include "manifold/model_metadata.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas::atlas {

namespace {

std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t h = 0xcbf29ce484222325ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

}  // namespace

std::string model_fingerprint(const Model& model) {
  const std::string meta = model.metadata().dump();
  std::uint64_t h = fnv1a(meta.data(), meta.size());
  const Eigen::MatrixXd& x = model.latent();
  h = fnv1a(x.data(), static_cast<std::size_t>(x.size()) * sizeof(double), h);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

render::ImageBasis render_basis(const Model& model, const render::Scene& scene,
                                const render::RenderSettings& settings, ProgressSink& progress) {
  const ModelBank bank(model);
  std::vector<Image> images = render::render_bank(scene, bank, settings, progress);
  Image mean = std::move(images.front());
  images.erase(images.begin());
  const render::SceneDescription& d = scene.description();
  std::map<std::string, std::string> meta;
  meta["scene"] = d.object + (d.ground ? "+ground" : "");
  meta["env"] = d.environment;
  meta["env_rotation"] = std::to_string(d.environment_rotation);
  meta["env_intensity"] = std::to_string(d.environment_intensity);
  meta["camera"] = nlohmann::json{{"orthographic", d.camera.orthographic},
                                  {"position", {d.camera.position.x(), d.camera.position.y(), d.camera.position.z()}},
                                  {"target", {d.camera.target.x(), d.camera.target.y(), d.camera.target.z()}},
                                  {"fov_degrees", d.camera.fov_degrees},
                                  {"ortho_height", d.camera.ortho_height}}
                       .dump();
  meta["lights"] = std::to_string(d.lights.size());
  meta["spp"] = std::to_string(settings.spp);
  meta["seed"] = std::to_string(settings.seed);
  meta["model"] = model.path().filename().string();
  meta["model_fingerprint"] = model_fingerprint(model);
  return render::ImageBasis(std::move(mean), images, model.names(), std::move(meta));
}

}  // namespace matlas::atlas
