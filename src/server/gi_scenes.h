#pragma once
// GiScenes: the scene view of the material browser (docs/GI.md, docs/WEB.md): per scene a GI
// image basis (atlas/gi_basis.h), composed at a map point's weights exactly as `matlas gi`
// composes it. A scene's basis is either a file made by `matlas basis --scene` (given at start-up,
// checked against the model) or traced in the background on the scene's first request (the
// built-in scenes, at a small default size), saved beside the model (MODEL.gi/) with its
// per-material cache, so that an interrupted build resumes and a restart loads it in a moment.
// While a scene is being traced its state says how far it got (server/preparations.h, the
// background service of the preview bases too).
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "formats/image_io.h"
#include "pathtrace/progressive_trace.h"
#include "pathtrace/tracer.h"

namespace matlas {
class Model;
}
namespace matlas::atlas {
class GiBasis;
}

namespace matlas::server {

/// The default trace settings of scenes traced on demand: small enough to finish in about a
/// minute on a few cores (256 x 192, 16 spp, max depth 8). The view at rest is refined at
/// GiSceneOptions::refine_width (512 x 384).
pathtrace::TraceSettings default_gi_trace();

struct GiSceneOptions {
  std::vector<std::filesystem::path> bases;           ///< from `matlas basis --scene`: served as they are
  std::vector<std::string> scenes = {"floor", "box"};  ///< traced on demand (built-in names or .json files)
  std::string object = "sphere";                       ///< the measured object of the built-in scenes
  pathtrace::TraceSettings trace = default_gi_trace();
  bool fit_density = true;  ///< trace.density := the model's fitted density (atlas/gi_density.h)
  int batch = 32;                                      ///< materials per tracing pass
  int max_refinements = 2;                             ///< points refined at rest kept in memory
  int refine_width = 512;                              ///< width of the refined image (the basis's aspect)
  std::filesystem::path cache_dir;                     ///< empty: MODEL.gi/ beside the model
  ToneMap tone{ToneMap::Curve::aces, 0.0};             ///< as `matlas gi` writes PNGs
};

/// Where a scene stands: its basis once ready; before that, how far its tracing got (or why it
/// failed).
struct GiSceneState {
  std::shared_ptr<const atlas::GiBasis> basis;
  double progress = 0.0;  ///< [0, 1]
  std::string stage;      ///< what is being done, for people
  std::string error;      ///< non-empty: the tracing failed
};

class GiScenes {
public:
  /// Loads options.bases; matlas::Error naming a file that is not a GI basis or was traced for
  /// another model. A given basis replaces the on-demand scene of the same name.
  GiScenes(const Model& model, GiSceneOptions options);
  ~GiScenes();
  GiScenes(const GiScenes&) = delete;
  GiScenes& operator=(const GiScenes&) = delete;

  /// The offered scenes: the given bases' first, then those traced on demand.
  const std::vector<std::string>& scenes() const;
  /// The scenes whose basis was given (ready from the start).
  std::vector<std::string> preloaded() const;
  /// Per built-in scene traced on demand, its camera views (pathtrace::builtin_views): the scene
  /// "NAME@VIEW" is offered too (its own basis, traced when first asked for).
  std::map<std::string, std::vector<std::string>> views() const;
  ToneMap tone() const;
  /// The file of a scene traced on demand (whether or not it exists yet).
  std::filesystem::path basis_path(const std::string& scene) const;

  /// The state of an offered scene; the first call for a scene not yet traced starts tracing it
  /// in the background. matlas::Error for a scene not offered (the message lists them).
  GiSceneState state(const std::string& scene) const;
  /// Blocks until the scene is ready and returns its basis (matlas::Error if tracing failed).
  std::shared_ptr<const atlas::GiBasis> wait(const std::string& scene) const;

  /// A refined image of the point `point` (a key: the same key, the same refinement; its weights
  /// are w) in `scene`: a direct progressive trace of m(x) at the scene's size and density
  /// (pathtrace/progressive_trace.h), refined for about `seconds` more. `progress` hears every
  /// row of a pass and may throw to stop it (the refinement stays as it was before that pass;
  /// the exception propagates). Needs no basis. matlas::Error for a scene not offered or one
  /// given only as a basis file (no scene to trace).
  /// With `denoise`, from the second pass on, the image is the refinement denoised from its two
  /// halves (ProgressiveTrace::denoised: biased; `denoised_error` the noise it estimates left,
  /// `state.relative_error` stays the plain mean's).
  struct Refined {
    Image image;
    render::RefinementState state;
    bool denoised = false;
    double denoised_error = 0;
  };
  Refined refine(const std::string& scene, const Eigen::VectorXd& w, const std::string& point, double seconds,
                 bool denoise, ProgressSink& progress) const;
  /// The refinement of `point` in `scene` as it stands (nothing traced), if there is one.
  std::optional<Refined> refined(const std::string& scene, const std::string& point, bool denoise) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace matlas::server
