#include "server/gi_scenes.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <utility>

#include <nlohmann/json.hpp>

#include "atlas/gi_basis.h"
#include "atlas/gi_density.h"
#include "atlas/model_material.h"
#include "core/error.h"
#include "manifold/model.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/world.h"
#include "server/http_error.h"
#include "server/lru_cache.h"
#include "server/preparations.h"

namespace matlas::server {

namespace {

/// A file-name-safe form of a scene or object name (a path gives its stem).
std::string file_part(const std::string& name) {
  std::string s = name.find_first_of("/.") == std::string::npos ? name : std::filesystem::path(name).stem().string();
  std::replace_if(s.begin(), s.end(), [](unsigned char c) { return !std::isalnum(c) && c != '-' && c != '_'; }, '_');
  return s;
}

}  // namespace

pathtrace::TraceSettings default_gi_trace() {
  pathtrace::TraceSettings s;
  s.width = 256;
  s.height = 192;
  s.spp = 16;
  s.max_depth = 8;
  return s;
}

struct GiScenes::Impl {
  const Model& model;
  GiSceneOptions options;
  std::vector<std::string> names;     // offered scenes
  std::vector<std::string> given;     // of them, those loaded from options.bases
  int passes = 1;                     // tracing passes of a scene (progress)

  /// Reports build_gi_basis's passes ("tracing materials a..b", then per row) as one fraction
  /// of the whole, each pass's line as the stage.
  class PassProgress final : public ProgressSink {
  public:
    PassProgress(ProgressSink& inner, int passes) : inner_(inner), passes_(passes) {}
    void update(const std::string&, std::uint64_t done, std::uint64_t total) override {
      const double pass = total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
      fraction_ = std::clamp(std::max(fraction_, (std::max(0, started_ - 1) + std::min(1.0, pass)) / passes_), 0.0, 1.0);
      inner_.update(line_, static_cast<std::uint64_t>(std::llround(fraction_ * kSteps)), kSteps);
    }
    void message(const std::string& line) override {
      ++started_;
      line_ = line;
      inner_.update(line_, static_cast<std::uint64_t>(std::llround(fraction_ * kSteps)), kSteps);
    }
    void finish(const std::string&) override {}

  private:
    static constexpr std::uint64_t kSteps = 1000000;
    ProgressSink& inner_;
    int passes_;
    int started_ = 0;
    double fraction_ = 0;
    std::string line_ = "tracing";
  };

  /// The scenes' bases: given ones put (and pinned) at start-up, the others traced in the
  /// background when first asked for. Made in the constructor, once the options are final.
  std::unique_ptr<Preparations<atlas::GiBasis>> bases;

  Impl(const Model& m, GiSceneOptions o) : model(m), options(std::move(o)) {
    if (options.fit_density) options.trace.density = atlas::fit_gi_density(model);
    options.trace.validate();
    if (options.batch <= 0) throw Error("GI scenes: the batch must be positive");
    passes = (model.count() + 1 + options.batch - 1) / options.batch;
    if (options.cache_dir.empty()) options.cache_dir = model.path().string() + ".gi";
    bases = std::make_unique<Preparations<atlas::GiBasis>>(
        [this](const std::string& scene, ProgressSink& progress) { return trace(scene, progress); },
        std::numeric_limits<std::size_t>::max());
    for (const auto& path : options.bases) {
      auto basis = std::make_shared<const atlas::GiBasis>(atlas::GiBasis::load(path));
      atlas::require_basis_of_model(*basis, model, path);
      std::string name = atlas::gi_basis_scene_name(*basis);
      if (name.empty()) name = path.stem().string();
      if (std::find(given.begin(), given.end(), name) != given.end())
        throw Error(path.string() + ": a second basis of the scene '" + name + "'");
      given.push_back(name);
      bases->pin(name);
      bases->put(name, std::move(basis));
    }
    names = given;
    for (const auto& s : options.scenes)
      if (std::find(names.begin(), names.end(), s) == names.end()) names.push_back(s);
  }

  std::filesystem::path basis_path(const std::string& scene) const {
    const auto& t = options.trace;
    return options.cache_dir / (file_part(scene) + "-" + file_part(options.object) + "-" + std::to_string(t.width) + "x" +
                                std::to_string(t.height) + "-" + std::to_string(t.spp) + "spp-s" +
                                std::to_string(t.seed) + ".safetensors");
  }

  /// Traces a scene's basis (or loads it from its file): on the worker of `bases`.
  std::shared_ptr<const atlas::GiBasis> trace(const std::string& scene, ProgressSink& progress) const {
    const pathtrace::World world(pathtrace::load_scene(scene, options.object));
    PassProgress passes_progress(progress, passes);
    std::filesystem::create_directories(options.cache_dir);
    return std::make_shared<const atlas::GiBasis>(
        atlas::open_or_build_gi_basis(model, world, options.trace, basis_path(scene), options.batch, passes_progress));
  }

  // Refinement at rest: per scene its world, per point a progressive trace (the last few).
  mutable std::mutex refine_mutex;
  mutable std::map<std::string, std::shared_ptr<const pathtrace::World>> worlds;
  mutable LruCache<std::shared_ptr<pathtrace::ProgressiveTrace>> refinements{
      static_cast<std::size_t>(std::max(1, options.max_refinements))};

  /// The world of an offered scene and the size of its images. Caller holds refine_mutex.
  std::pair<std::shared_ptr<const pathtrace::World>, std::pair<int, int>> world_of(const std::string& scene) const {
    require_offered(scene);
    const std::shared_ptr<const atlas::GiBasis> given_basis =
        std::find(given.begin(), given.end(), scene) != given.end() ? bases->find(scene) : nullptr;
    auto& world = worlds[scene];
    if (!world) {
      if (given_basis) {
        const auto& meta = given_basis->metadata();
        const auto it = meta.find("scene");
        if (it == meta.end()) throw Error("the GI basis of '" + scene + "' names no scene to refine");
        world = std::make_shared<const pathtrace::World>(pathtrace::parse_scene(nlohmann::json::parse(it->second), scene));
      } else {
        world = std::make_shared<const pathtrace::World>(pathtrace::load_scene(scene, options.object));
      }
    }
    // The refined image: refine_width wide, at the basis's aspect.
    const int w = options.refine_width;
    const int h = given_basis ? std::max(1, static_cast<int>(std::lround(static_cast<double>(w) * given_basis->height() / given_basis->width())))
                              : std::max(1, static_cast<int>(std::lround(static_cast<double>(w) * options.trace.height / options.trace.width)));
    const std::pair<int, int> size(w, h);
    return {world, size};
  }

  void require_offered(const std::string& scene) const {
    if (std::find(names.begin(), names.end(), scene) != names.end()) return;
    // NAME@VIEW: a view of a built-in scene traced on demand.
    if (const auto at = scene.find('@'); at != std::string::npos) {
      const std::string base = scene.substr(0, at);
      const auto views = pathtrace::builtin_views(base);
      if (std::find(options.scenes.begin(), options.scenes.end(), base) != options.scenes.end() &&
          std::find(given.begin(), given.end(), base) == given.end() &&
          std::find(views.begin(), views.end(), scene.substr(at + 1)) != views.end())
        return;
    }
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw Error("unknown GI scene " + quoted_excerpt(scene) + "; offered: " + (list.empty() ? "none" : list));
  }

  /// The state of an offered scene, queueing it when it is new.
  GiSceneState state(const std::string& scene) const {
    require_offered(scene);
    const auto s = bases->request(scene);
    return GiSceneState{s.value, s.progress, s.stage, s.error};
  }
};

GiScenes::GiScenes(const Model& model, GiSceneOptions options)
    : impl_(std::make_unique<Impl>(model, std::move(options))) {}

GiScenes::~GiScenes() = default;

const std::vector<std::string>& GiScenes::scenes() const { return impl_->names; }
std::vector<std::string> GiScenes::preloaded() const { return impl_->given; }

std::map<std::string, std::vector<std::string>> GiScenes::views() const {
  std::map<std::string, std::vector<std::string>> out;
  for (const auto& s : impl_->names)
    if (std::find(impl_->given.begin(), impl_->given.end(), s) == impl_->given.end())
      if (auto v = pathtrace::builtin_views(s); !v.empty()) out[s] = std::move(v);
  return out;
}
ToneMap GiScenes::tone() const { return impl_->options.tone; }
std::filesystem::path GiScenes::basis_path(const std::string& scene) const { return impl_->basis_path(scene); }

GiSceneState GiScenes::state(const std::string& scene) const { return impl_->state(scene); }

std::shared_ptr<const atlas::GiBasis> GiScenes::wait(const std::string& scene) const {
  impl_->require_offered(scene);
  const auto s = impl_->bases->wait(scene);
  if (!s.value) throw Error("the GI scene '" + scene + "' failed: " + s.error);
  return s.value;
}

namespace {

GiScenes::Refined refined_image(const pathtrace::ProgressiveTrace& trace, const render::RefinementState& state,
                                bool denoise) {
  GiScenes::Refined out;
  out.state = state;
  if (denoise && state.passes >= 2) {
    render::DenoiseResult d = trace.denoised();
    out.image = std::move(d.image);
    out.denoised = true;
    out.denoised_error = d.relative_error;
  } else {
    out.image = trace.image();
  }
  return out;
}

}  // namespace

GiScenes::Refined GiScenes::refine(const std::string& scene, const Eigen::VectorXd& w, const std::string& point,
                                   double seconds, bool denoise, ProgressSink& progress) const {
  Impl& im = *impl_;
  const std::string key = scene + "|" + point;
  std::shared_ptr<pathtrace::ProgressiveTrace> trace;
  {
    std::lock_guard lock(im.refine_mutex);
    if (const auto* found = im.refinements.find(key)) {
      trace = *found;
    } else {
      const auto [world, size] = im.world_of(scene);
      pathtrace::ProgressiveTraceSettings settings;
      settings.trace = im.options.trace;
      settings.trace.width = size.first;
      settings.trace.height = size.second;
      settings.trace.spp = 1;
      trace = std::make_shared<pathtrace::ProgressiveTrace>(
          world, atlas::model_point_bank(im.model, w), settings);
      im.refinements.put(key, trace);
    }
  }
  const render::RefinementState state = trace->refine(seconds, progress);
  return refined_image(*trace, state, denoise);
}

std::optional<GiScenes::Refined> GiScenes::refined(const std::string& scene, const std::string& point,
                                                   bool denoise) const {
  std::shared_ptr<pathtrace::ProgressiveTrace> trace;
  {
    std::lock_guard lock(impl_->refine_mutex);
    const auto* found = impl_->refinements.peek(scene + "|" + point);
    if (!found) return std::nullopt;
    trace = *found;
  }
  return refined_image(*trace, trace->state(), denoise);
}

}  // namespace matlas::server
