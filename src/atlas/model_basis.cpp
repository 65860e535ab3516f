#include "atlas/model_basis.h"

#include <map>
#include <vector>

#include "atlas/model_bank.h"
#include "atlas/sampling_fit.h"
#include "core/check.h"
#include "core/hash.h"
#include "manifold/model_metadata.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas::atlas {

std::string model_fingerprint(const Model& model) {
  Xxh3Hasher h;
  h.update(model.metadata().dump());
  const Eigen::MatrixXd& x = model.latent();
  h.update(x.data(), static_cast<std::size_t>(x.size()) * sizeof(double));
  return hex64(h.digest());
}

std::string sampling_record(const render::RenderSettings& settings) {
  const render::SamplingMixture& m = settings.mixture;
  nlohmann::json lobes = nlohmann::json::array();
  for (const auto& [alpha, weight] : m.lobes) lobes.push_back({alpha, weight});
  const std::vector<double>& profile = m.profile();
  Xxh3Hasher h;
  h.update(profile.data(), profile.size() * sizeof(double));
  const char* sampler = settings.sampler == render::Sampler::light_and_lobe ? "light_and_lobe"
                        : settings.sampler == render::Sampler::stratified   ? "stratified"
                                                                             : "independent";
  return nlohmann::json{{"sampler", sampler},
                        {"power_heuristic", settings.power_heuristic},
                        {"environment", m.environment},
                        {"cosine", m.cosine},
                        {"lobes", lobes},
                        {"tabulated", m.tabulated},
                        {"profile_hash", hex64(h.digest())}}
      .dump();
}

render::ImageBasis render_basis(const Model& model, const render::Scene& scene,
                                const render::RenderSettings& requested, ProgressSink& progress) {
  const ModelBank bank(model);
  const render::RenderSettings settings = model_render_settings(model, requested);
  std::vector<Image> images = render::render_bank(scene, bank, settings, progress);
  MATLAS_CHECK_EQ(images.size(), static_cast<std::size_t>(model.count()) + 1);  // the mean, then the n materials
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
  meta["sampling_mixture"] = sampling_record(settings);
  meta["model"] = model.path().filename().string();
  meta["model_fingerprint"] = model_fingerprint(model);
  return render::ImageBasis(std::move(mean), images, model.names(), std::move(meta));
}

}  // namespace matlas::atlas
