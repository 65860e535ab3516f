#include "atlas/model_basis.h"

#include <algorithm>
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

std::vector<Image> gather_images(std::vector<Image> mine, Communicator& comm) {
  if (comm.size() == 1) return mine;
  const int width = mine.empty() ? 0 : mine.front().width, height = mine.empty() ? 0 : mine.front().height;
  std::vector<std::vector<float>> rgb;
  for (Image& image : mine) rgb.push_back(std::move(image.rgb));
  std::vector<Image> all;
  for (auto& pixels : gather_arrays(comm, rgb)) {
    Image& image = all.emplace_back();
    image.width = width;  // rank 0 has images whenever any rank has: it holds the first share
    image.height = height;
    image.rgb = std::move(pixels);
    MATLAS_CHECK_EQ(image.rgb.size(), image.pixel_count() * 3);
  }
  return all;
}

std::vector<Image> gather_rows(std::vector<Image> mine, int height, Communicator& comm) {
  if (comm.size() == 1) return mine;
  const std::size_t count = mine.size();
  const int width = mine.empty() ? 0 : mine.front().width;
  std::vector<std::vector<float>> rgb;
  for (Image& image : mine) rgb.push_back(std::move(image.rgb));
  std::vector<std::vector<float>> all = gather_arrays(comm, rgb);
  if (!comm.is_root()) return {};
  const auto ranks = static_cast<std::size_t>(comm.size());
  MATLAS_CHECK_EQ(all.size(), count * ranks);  // every rank renders every image
  std::vector<Image> images(count, Image(width, height));
  const std::size_t row_floats = static_cast<std::size_t>(width) * 3;
  for (std::size_t r = 0; r < ranks; ++r) {
    const render::RowShare share{static_cast<int>(r), comm.size()};
    for (std::size_t k = 0; k < count; ++k) {
      const std::vector<float>& part = all[r * count + k];
      MATLAS_CHECK_EQ(part.size(), static_cast<std::size_t>(share.rows(height)) * row_floats);
      for (int j = 0; j < share.rows(height); ++j)
        std::copy_n(part.data() + static_cast<std::size_t>(j) * row_floats, row_floats, images[k].pixel(0, share.row(j)));
    }
  }
  return images;
}

render::ImageBasis render_basis(const Model& model, const render::Scene& scene,
                                const render::RenderSettings& requested, ProgressSink& progress, Communicator& comm) {
  const render::RenderSettings settings = model_render_settings(model, requested);
  // Every rank renders its share of the rows (every P-th) for all n + 1 materials: a pixel's
  // samples depend on the pixel only, so the shares' rows are the single process's. (A share of
  // the materials would not divide the work: a camera sample's cost is mostly its path and its
  // lookups, not the number of materials evaluated with it.)
  const render::RowShare share{comm.rank(), comm.size()};
  std::vector<Image> images;
  run_collectively(comm, [&] {
    const ModelBank bank(model);
    images = render::render_bank(scene, bank, settings, progress, nullptr, share);
  });
  images = gather_rows(std::move(images), settings.height, comm);
  if (!comm.is_root()) return {};
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
