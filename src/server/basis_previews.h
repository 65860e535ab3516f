#pragma once
// BasisPreviews: the renderer-backed PreviewSource. For each offered scene (environment x object)
// an image basis (render/image_basis.h) turns a preview into one linear combination of n images,
// plus a half-resolution copy of it for the smaller previews sent while dragging (composed through
// its low-rank form when that is at most half the size: same image to about 0.2%, faster; exactly
// when the weights name fewer materials than its rank, as convex weights do).
//
// Bases are rendered once per scene and cached on disk (cache_dir, keyed by the model's
// fingerprint, the scene and the render settings), so a restart loads them in a moment. The
// default scene is prepared before serving (prepare_default); any other scene is rendered in the
// background on its first request (server/preparations.h), which gets 503 "being prepared"
// meanwhile. At most `max_loaded` bases stay in memory (least recently used dropped).
//
// Refinement: the point a user rests on is rendered directly (render/progressive_render.h): its
// table is built once (atlas::ModelTableMaterial), sampled with the defensive mixture of the one
// fitted to that material and the database's (atlas::defensive_mixture), and
// refined pass after pass while the client keeps asking; the image never mixes basis and direct
// samples. The last `max_refinements` points stay (each holds its table, about 35 MB). From the
// second pass on the refinement tries the point's rotated-ZH shading as a control variate (its
// coefficients projected from the table, 0.1-0.2 s; the environment prefiltered in the background
// once, about 80 MB, the last two kept; plain passes until it is ready) and keeps it where it is
// less noisy than the plain estimate.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/progress.h"
#include "server/preview_source.h"

namespace matlas {
class Model;
}

namespace matlas::server {

struct BasisPreviewOptions {
  std::vector<std::string> environments;  ///< empty: the installed maps (else "constant"); first = default
  std::vector<std::string> objects;       ///< empty: "sphere" and the installed meshes; first = default
  std::string default_environment = "studio";  ///< used when offered
  int size = 256;                         ///< full preview side
  int spp = 32;                           ///< samples per pixel of the basis renders
  std::uint64_t seed = 1;
  ToneMap tone{ToneMap::Curve::aces, 0.0};
  std::filesystem::path cache_dir;        ///< empty: no disk cache
  int max_loaded = 4;
  /// Relative error allowed for the low-rank form of the half-size (drag) basis; 0: exact.
  double drag_tolerance = 2e-3;
  /// Refinement: points kept, the first pass's samples, and the error at which it stops.
  int max_refinements = 4;
  int refine_first_spp = 16;
  double refine_target_error = 0.004;
  /// Refinements render with the real-time shading as a control variate (zonal/control_variate.h)
  /// where it is the less noisy estimate (docs/RENDERING.md "Control variate").
  bool control_variate = true;
};

class BasisPreviews final : public PreviewSource {
public:
  BasisPreviews(const Model& model, BasisPreviewOptions options);
  ~BasisPreviews() override;

  /// Renders (or loads from the cache) the default scene's basis now.
  void prepare_default(ProgressSink& progress = null_progress());
  /// Path of the cached basis of a scene (whether or not it exists yet).
  std::filesystem::path cache_path(const std::string& environment, const std::string& object) const;

  std::vector<std::string> environments() const override;
  std::vector<std::string> objects() const override;
  std::string default_environment() const override;
  std::string default_object() const override;
  int size() const override;
  int drag_size() const override;
  ToneMap tone() const override;
  Image render(const Eigen::VectorXd& w, const std::string& environment, const std::string& object,
               int size) const override;
  SceneStatus status(const std::string& environment, const std::string& object) const override;
  Refined refine(const Eigen::VectorXd& w, const std::string& point, const std::string& environment,
                 const std::string& object, double seconds, bool denoise,
                 ProgressSink& progress = null_progress()) const override;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace matlas::server
