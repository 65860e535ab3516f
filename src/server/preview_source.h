#pragma once
// PreviewSource: what the server needs to show a material: a linear RGB image of m(x), given its
// weights w(x), for one of the offered environments and objects. The renderer-backed source is
// BasisPreviews (server/basis_previews.h): per scene an image basis, composed linearly, and a
// progressive render of the point the user rests on.
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "formats/image_io.h"
#include "render/progressive_render.h"
#include "server/http_error.h"

namespace matlas::server {

class PreviewSource {
public:
  virtual ~PreviewSource() = default;
  virtual std::vector<std::string> environments() const = 0;
  virtual std::vector<std::string> objects() const = 0;
  virtual std::string default_environment() const = 0;
  virtual std::string default_object() const = 0;
  /// Side of the full-size preview in pixels, and of the smaller one sent while dragging.
  virtual int size() const = 0;
  virtual int drag_size() const = 0;
  /// The display transform of preview images.
  virtual ToneMap tone() const = 0;
  /// The image of the material with weights w (side `size` or `drag_size`, or any other side
  /// the source supports by resampling). Throws HttpError(503) while the scene is still being
  /// prepared and HttpError(400) for an unknown scene.
  virtual Image render(const Eigen::VectorXd& w, const std::string& environment,
                       const std::string& object, int size) const = 0;

  /// Where a scene's previews stand: ready, or how far their preparation got (or why it failed).
  struct SceneStatus {
    bool ready = true;
    double progress = 1.0;     ///< [0, 1]
    std::string stage;         ///< what is being done, for people
    double seconds = 0;        ///< since the preparation started
    double seconds_left = -1;  ///< estimated from the rate so far; < 0: not known yet
    std::string error;         ///< non-empty: the preparation failed
  };
  /// The status of an offered scene; asking for a scene not prepared yet starts preparing it (as
  /// render() does) without answering 503. Unknown scenes: HttpError(400).
  virtual SceneStatus status(const std::string& /*environment*/, const std::string& /*object*/) const { return {}; }

  /// What a progress sink throws to stop a refinement's pass early: refine() then returns the
  /// state as it was before that pass, with `interrupted` set.
  struct Interrupt {};
  /// A refined full-size image of the material with weights w, and how far it has converged.
  struct Refined {
    Image image;
    render::RefinementState state;  ///< of the plain mean (its error estimate is unbiased)
    bool interrupted = false;
    bool denoised = false;           ///< image is the mean denoised (render/denoise.h: biased)
    double denoised_error = std::numeric_limits<double>::infinity();  ///< its noise estimate
  };
  /// Refines the image of the point `point` (a key: the same key, the same refinement; its
  /// weights are w) for about `seconds` more and returns it, denoised if `denoise`. `progress`
  /// hears every row of a pass and may throw Interrupt to stop it (the refinement stays as it was
  /// before that pass).
  /// Sources without refinement answer 404; unknown scenes 400.
  virtual Refined refine(const Eigen::VectorXd& /*w*/, const std::string& /*point*/,
                         const std::string& /*environment*/, const std::string& /*object*/,
                         double /*seconds*/, bool /*denoise*/, ProgressSink& /*progress*/ = null_progress()) const {
    throw HttpError(404, "this server does not refine previews");
  }
};

}  // namespace matlas::server
