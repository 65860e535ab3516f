#include "server/basis_previews.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <mutex>

#include "atlas/model_basis.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "core/error.h"
#include "formats/image_resize.h"
#include "manifold/model.h"
#include "render/assets.h"
#include "render/progressive_render.h"
#include "render/render.h"
#include "render/scene.h"
#include "server/cancellable_sink.h"
#include "server/http_error.h"
#include "server/lru_cache.h"
#include "server/preparations.h"
#include "zonal/control_variate.h"
#include "zonal/projection.h"

namespace matlas::server {

namespace {

std::string safe_name(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out;
}

}  // namespace

struct BasisPreviews::Impl {
  const Model& model;
  BasisPreviewOptions options;
  std::string fingerprint;
  std::vector<std::string> envs, objects;

  struct Entry {
    std::shared_ptr<const render::ImageBasis> full, half;
  };

  /// Refinements (point, scene) and the last two scenes they render, least recently used dropped.
  mutable std::mutex refine_mutex;
  mutable LruCache<std::shared_ptr<render::ProgressiveRender>> refinements{
      static_cast<std::size_t>(std::max(1, options.max_refinements))};
  mutable LruCache<std::shared_ptr<const render::Scene>> scenes{2};
  /// The control variate's projector (built on first use) and prefiltered environments by name
  /// (prepared in the background: about 1 s each, the last two kept).
  mutable std::mutex control_mutex;
  mutable std::shared_ptr<const zonal::ZonalProjector> projector;
  mutable MerlDims projector_dims;  ///< the table size it projects
  mutable Preparations<zonal::PrefilteredEnvironment> control_environments{
      [](const std::string& environment, ProgressSink&) {
        render::SceneDescription desc;
        desc.environment = environment;
        return std::make_shared<const zonal::PrefilteredEnvironment>(render::Scene(desc).environment(),
                                                                     zonal::control_prefilter_settings());
      },
      2};
  /// The database's sampling mixture (the bases'), fitted once: half of every refinement's.
  render::SamplingMixture database_mixture;
  /// The bases, prepared in the background by key(env, object); the default scene's is pinned.
  /// Last: its worker uses the members above.
  Preparations<Entry> bases{[this](const std::string& k, ProgressSink& progress) {
                              const auto split = k.find('\n');
                              return std::make_shared<const Entry>(build(k.substr(0, split), k.substr(split + 1), progress));
                            },
                            static_cast<std::size_t>(std::max(1, options.max_loaded))};

  /// The table's rotated-ZH shading under the environment as a control variate; null while the
  /// environment's maps are being prepared (the refinement goes on plain and asks again).
  std::shared_ptr<const render::ControlVariate> control_variate(const BrdfTable& table, const std::string& environment) const {
    const auto env = control_environments.request(environment).value;
    if (!env) return nullptr;
    std::shared_ptr<const zonal::ZonalProjector> p;
    MerlDims held;
    {
      std::lock_guard lock(control_mutex);
      p = projector;
      held = projector_dims;
    }
    // Built outside the lock (once per table size); concurrent builders agree.
    const MerlDims& dims = table.dims();
    const auto same = [&](const MerlDims& d) { return d.theta_h == dims.theta_h && d.theta_d == dims.theta_d && d.phi_d == dims.phi_d; };
    if (!p || !same(held)) {
      p = std::make_shared<const zonal::ZonalProjector>(zonal::control_projection_settings(), dims);
      std::lock_guard lock(control_mutex);
      projector = p;
      projector_dims = dims;
    }
    return std::make_shared<const zonal::ZonalControlVariate>(p->project(table), env);
  }

  Impl(const Model& m, BasisPreviewOptions o) : model(m), options(std::move(o)) {
    fingerprint = atlas::model_fingerprint(model);
    envs = options.environments;
    if (envs.empty()) {
      envs = installed_environments();
      if (envs.empty()) envs.push_back("constant");
    }
    if (const auto it = std::find(envs.begin(), envs.end(), options.default_environment); it != envs.end())
      std::rotate(envs.begin(), it, it + 1);
    objects = options.objects;
    if (objects.empty()) {
      objects.push_back("sphere");
      for (const char* mesh : {"bunny", "suzi"}) {
        try {
          resolve_mesh(mesh);
          objects.emplace_back(mesh);
        } catch (const Error&) {
        }
      }
    }
    bases.pin(key(envs.front(), objects.front()));
    database_mixture = atlas::model_render_settings(model, settings()).mixture;
  }

  static std::string key(const std::string& env, const std::string& object) { return env + "\n" + object; }

  std::filesystem::path cache_path(const std::string& env, const std::string& object) const {
    if (options.cache_dir.empty()) return {};
    return options.cache_dir / ("basis-" + fingerprint + "-" + safe_name(env) + "-" + safe_name(object) + "-" +
                                std::to_string(options.size) + "px-" + std::to_string(options.spp) + "spp-s" +
                                std::to_string(options.seed) + ".safetensors");
  }

  /// The preview bases' render settings (render_basis fits the mixture to the model).
  render::RenderSettings settings() const {
    render::RenderSettings s;
    s.width = s.height = options.size;
    s.spp = options.spp;
    s.seed = options.seed;
    return s;
  }

  Entry build(const std::string& env, const std::string& object, ProgressSink& progress) const {
    const auto path = cache_path(env, object);
    std::shared_ptr<render::ImageBasis> full;
    if (!path.empty() && std::filesystem::exists(path)) {
      try {
        auto b = std::make_shared<render::ImageBasis>(render::ImageBasis::open(path));
        const auto& meta = b->metadata();
        const auto fp = meta.find("model_fingerprint");
        const auto sampling = meta.find("sampling_mixture");
        if (b->count() == model.count() && b->width() == options.size && fp != meta.end() && fp->second == fingerprint &&
            sampling != meta.end() && sampling->second == atlas::sampling_record(atlas::model_render_settings(model, settings())))
          full = std::move(b);  // else rendered with another sampler or mixture (an older matlas): render again
      } catch (const Error&) {
        // A damaged or foreign cache file: render again and replace it.
      }
    }
    if (!full) {
      render::SceneDescription desc;
      desc.environment = env;
      desc.object = object;
      const render::Scene scene(desc);
      full = std::make_shared<render::ImageBasis>(atlas::render_basis(model, scene, settings(), progress));
      full->convert_to_half();
      if (!path.empty()) {
        std::filesystem::create_directories(path.parent_path());
        full->save(path, render::BasisPrecision::f16);
      }
    }
    // The half-resolution basis for drag previews: the same images, area-averaged.
    const int half = std::max(16, options.size / 2);
    std::vector<Image> images;
    images.reserve(static_cast<std::size_t>(full->count()));
    for (int i = 0; i < full->count(); ++i) images.push_back(resize_area(full->material_image(i), half, half));
    auto small = std::make_shared<render::ImageBasis>(resize_area(full->mean_image(), half, half), images);
    // Drag previews go through the low-rank form when it is much smaller (fewer values to read).
    if (options.drag_tolerance > 0) {
      small->compress(options.drag_tolerance);
      if (small->low_rank() * 2 > small->count()) small = std::make_shared<render::ImageBasis>(
          resize_area(full->mean_image(), half, half), images);
    }
    if (small->low_rank() == 0) small->convert_to_half();
    return Entry{full, small};
  }

};

BasisPreviews::SceneStatus BasisPreviews::status(const std::string& environment, const std::string& object) const {
  auto& im = *impl_;
  if (std::find(im.envs.begin(), im.envs.end(), environment) == im.envs.end() ||
      std::find(im.objects.begin(), im.objects.end(), object) == im.objects.end())
    throw HttpError(400, "no preview scene (" + quoted_excerpt(environment) + ", " + quoted_excerpt(object) + ")");
  const auto prepared = im.bases.request(Impl::key(environment, object));
  if (prepared.value) return {};
  SceneStatus s;
  s.ready = false;
  s.progress = prepared.progress;
  s.stage = prepared.stage;
  s.seconds = prepared.seconds;
  s.seconds_left = prepared.seconds_left;
  s.error = prepared.error;
  return s;
}

BasisPreviews::Refined BasisPreviews::refine(const Eigen::VectorXd& w, const std::string& point,
                                             const std::string& environment, const std::string& object,
                                             double seconds, bool denoise, ProgressSink& progress) const {
  auto& im = *impl_;
  if (std::find(im.envs.begin(), im.envs.end(), environment) == im.envs.end() ||
      std::find(im.objects.begin(), im.objects.end(), object) == im.objects.end())
    throw HttpError(400, "no preview scene (" + quoted_excerpt(environment) + ", " + quoted_excerpt(object) + ")");
  const std::string scene_key = Impl::key(environment, object);
  const std::string key = point + "\n" + scene_key;
  std::shared_ptr<render::ProgressiveRender> refinement;
  std::shared_ptr<const render::Scene> scene;
  {
    std::lock_guard lock(im.refine_mutex);
    if (const auto* found = im.refinements.find(key)) refinement = *found;
    else if (const auto* known = im.scenes.find(scene_key)) scene = *known;
  }
  if (!refinement) {
    // Built outside the lock (a scene and a table take a few hundred milliseconds); a
    // concurrent request for the same point may build it too, the first one inserted wins.
    if (!scene) {
      render::SceneDescription desc;
      desc.environment = environment;
      desc.object = object;
      scene = std::make_shared<const render::Scene>(desc);
    }
    auto material = std::make_shared<const atlas::ModelTableMaterial>(im.model, w);
    render::ProgressiveSettings settings;
    settings.render.width = settings.render.height = im.options.size;
    settings.render.spp = im.options.refine_first_spp;
    settings.render.seed = im.options.seed + 0x5DEECE66Dull;  // not the basis' samples
    // Sampling: the mixture fitted to this one table, made defensive with the database's (the
    // bases'): neither alone is best for every material (docs/RENDERING.md "Refinement").
    settings.render.mixture = atlas::defensive_mixture(
        atlas::fit_sampling_mixture(render::MaterialList({material.get()}),
                                    atlas::SamplingFitOptions::for_sampler(settings.render.sampler)),
        im.database_mixture);
    settings.limits.target_error = im.options.refine_target_error;
    settings.shown = im.options.tone;  // adaptive sampling weighs the error as the page shows it too
    if (im.options.control_variate)  // made by the second pass (the material and the scene outlive the refinement)
      settings.control_variate = [&im, material = material.get(), environment] {
        return im.control_variate(material->table(), environment);
      };
    auto made = std::make_shared<render::ProgressiveRender>(scene, material, settings);
    std::lock_guard lock(im.refine_mutex);
    refinement = *im.refinements.put(key, std::move(made), /*keep_existing=*/true);
    im.scenes.put(scene_key, scene);
  }
  CancellableSink sink(progress, im.bases.stopping());
  Refined out;
  try {
    out.state = refinement->refine(seconds, sink);
  } catch (const Interrupt&) {
    out.state = refinement->state();
    out.interrupted = true;
  } catch (const Cancelled&) {
    throw HttpError(503, "the server is shutting down");
  }
  if (denoise && out.state.passes >= 2) {
    render::DenoiseResult d = refinement->denoised();
    out.image = std::move(d.image);
    out.denoised = true;
    out.denoised_error = d.relative_error;
  } else {
    out.image = refinement->image();
  }
  return out;
}

BasisPreviews::BasisPreviews(const Model& model, BasisPreviewOptions options)
    : impl_(std::make_unique<Impl>(model, std::move(options))) {}

BasisPreviews::~BasisPreviews() = default;

void BasisPreviews::prepare_default(ProgressSink& progress) {
  const auto& env = impl_->envs.front();
  const auto& object = impl_->objects.front();
  impl_->bases.put(Impl::key(env, object), std::make_shared<const Impl::Entry>(impl_->build(env, object, progress)));
}

std::filesystem::path BasisPreviews::cache_path(const std::string& environment, const std::string& object) const {
  return impl_->cache_path(environment, object);
}

std::vector<std::string> BasisPreviews::environments() const { return impl_->envs; }
std::vector<std::string> BasisPreviews::objects() const { return impl_->objects; }
std::string BasisPreviews::default_environment() const { return impl_->envs.front(); }
std::string BasisPreviews::default_object() const { return impl_->objects.front(); }
int BasisPreviews::size() const { return impl_->options.size; }
int BasisPreviews::drag_size() const { return std::max(16, impl_->options.size / 2); }
ToneMap BasisPreviews::tone() const { return impl_->options.tone; }

Image BasisPreviews::render(const Eigen::VectorXd& w, const std::string& environment, const std::string& object,
                            int size) const {
  const auto prepared = impl_->bases.request(Impl::key(environment, object));
  if (!prepared.error.empty())
    throw HttpError(500, "the preview scene (" + environment + ", " + object + ") failed: " + prepared.error);
  if (!prepared.value)
    throw HttpError(503, "the preview scene (" + environment + ", " + object +
                             ") is being prepared; try again in a few seconds");
  const std::shared_ptr<const render::ImageBasis> full = prepared.value->full, half = prepared.value->half;
  Image image = size <= half->width() ? half->compose_fast(w) : full->compose(w);
  if (image.width != size) image = resize_area(image, size, size);
  return image;
}

}  // namespace matlas::server
