#pragma once
// Api: the JSON API of the material browser (docs/API.md), independent of the HTTP library: each
// endpoint takes the request body (and parameters) and returns a Reply. Invalid requests throw
// HttpError with a 4xx status and a message; AtlasServer turns it into {"error": message}.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "manifold/export.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"
#include "render/refinement.h"
#include "server/atlas_server.h"
#include "server/compute_gate.h"
#include "server/png_cache.h"
#include "server/point_weights.h"
#include "server/preview_generations.h"
#include "server/realtime.h"
#include "server/request_parsing.h"

namespace matlas::atlas {
class GiBasis;
}

namespace matlas::server {

/// The content type of every image the API answers.
inline constexpr const char* kPng = "image/png";

struct Reply {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;

  static Reply json(const nlohmann::json& j);
  static Reply bytes(std::string data, std::string content_type);
};

class Api {
public:
  Api(const Model& model, std::shared_ptr<const PreviewSource> previews, const ServerOptions& options);

  /// GET /api/model
  Reply model_info() const;
  /// POST /api/preview {"x", "env", "object", "size"} -> PNG
  Reply preview(const std::string& body);
  /// GET /api/preview/status?env=&object=: whether the scene's previews are ready, else how far
  /// their preparation got (starts it; never 503)
  Reply preview_status(const std::string& env, const std::string& object) const;
  /// POST /api/preview/refine {"x", "env", "object", "seconds"} -> PNG of the point refined for
  /// about `seconds` more (X-Matlas-Spp, X-Matlas-Error, X-Matlas-Converged, X-Matlas-Seconds)
  Reply preview_refine(const std::string& body);
  /// GET /api/thumbnail/INDEX?env=&object=&size= -> PNG
  Reply thumbnail(int index, const std::string& env, const std::string& object, int size);
  /// POST /api/weights {"x", "top"}
  Reply weights(const std::string& body);
  /// GET /api/interpolation: what a client needs to compute the weights itself (JSON)
  Reply interpolation() const;
  /// POST /api/slice {"x", "phi_d"} -> PNG
  Reply slice(const std::string& body);
  /// POST /api/lobe {"x", "theta_i", "samples"}
  Reply lobe(const std::string& body);
  /// POST /api/albedo {"x"}
  Reply albedo(const std::string& body);
  /// POST /api/map {"layer", "axes", "x", "rect", "size"} -> PNG
  Reply map_layer(const std::string& body);
  /// POST /api/export {"x", "material", "format"} -> the table as MERL .binary (format "binary", the
  /// default) or RGL .bsdf ("bsdf", Mitsuba 3 / pbrt-v4) (server/export_api.cpp)
  Reply export_file(const std::string& body);
  /// POST /api/fit {"x", "material"} -> the analytic fit's report with its error (artist/fit_report.h)
  Reply fit(const std::string& body);
  /// POST /api/fit/file {"x", "material", "format": "gltf" | "mtlx" | "py"} -> the fitted material
  /// as a glTF 2.0 document, a MaterialX document or a Blender script (the fit kept from /api/fit)
  Reply fit_file(const std::string& body);
  /// POST /api/project: a MERL .binary file as the body -> its latent point and residual
  Reply project(const std::string& file_bytes);
  /// POST /api/fit-samples: a sample file (CSV or JSON, formats/sample_file.h) as the body -> the
  /// latent point that explains it, its covariance, weights and the residual of every sample
  /// (server/acquisition_api.cpp); `robust` "0" fits by least squares
  Reply fit_samples(const std::string& file_text, const std::string& robust = "");
  /// POST /api/sample-plan?k=K: the K directions to measure next (the body: samples so far, or empty)
  Reply sample_plan(const std::string& file_text, const std::string& k);

  /// GET /api/realtime: the real-time viewer's shapes and basis (JSON)
  Reply realtime_info();
  /// GET /api/realtime/coefficients: float32 coefficients of the mean and every material
  Reply realtime_coefficients();
  /// GET /api/realtime/environment/NAME: float32 prefiltered band maps (shape in X-Matlas-Shape)
  Reply realtime_environment(const std::string& name);
  /// GET /api/realtime/mesh/NAME: an installed mesh, decoded and placed as the renderer does
  Reply realtime_mesh(const std::string& name);
  /// POST /api/realtime/lights {"x"} -> float16 light table of the point (the direct lights')
  Reply realtime_lights(const std::string& body);
  /// POST /api/realtime/reference {"x", "env", "rotation", "exposure", "size"} -> RGBA PNG
  Reply realtime_reference(const std::string& body);
  /// POST /api/realtime/reference/radiance (same body) -> float32 RGBA before tone mapping
  Reply realtime_reference_radiance(const std::string& body);

  /// GET /api/gi?scene=&x=&exposure=&tone= -> PNG: the scene view (503 while the scene is traced);
  /// exposure "auto": the scene's automatic exposure (render/auto_exposure.h)
  Reply gi(const std::string& scene, const std::string& x, const std::string& exposure,
           const std::string& tone = "");

  /// POST /api/gi/refine {"scene", "x", "seconds", "exposure", "tone"} -> PNG of the point refined
  /// by a direct progressive trace (GiScenes::refine), with X-Matlas-Spp, -Error, -Converged,
  /// -Seconds, -Exposure; a GET /api/gi of the same client stops the pass under way
  /// (X-Matlas-Interrupted).
  Reply gi_refine(const std::string& body);

  const LatentDomain& domain() const { return domain_; }
  const ComputeGate& compute_gate() const { return compute_; }

private:
  /// The key of a latent point for caches and refinements (every coordinate to 17 digits).
  static std::string point_key(const Eigen::VectorXd& x);
  /// model_.weights(x), solved once for the several requests a drag step makes (PointWeights).
  Eigen::VectorXd weights_at(const Eigen::VectorXd& x) const { return point_weights_.weights(x, point_key(x)); }
  /// The headers of a refinement's answer (previews and the scene view): X-Matlas-Spp, -Error,
  /// -Converged, -Seconds, -Interrupted; never cached.
  static void add_refinement_headers(Reply& r, const render::RefinementState& state, bool interrupted);
  /// X-Matlas-Denoised: 1 and X-Matlas-Denoised-Error (the noise the denoiser estimates left) for
  /// a denoised refinement; nothing otherwise.
  static void add_denoised_headers(Reply& r, bool denoised, double denoised_error);
  Reply reference_reply(const std::string& body, bool radiance);
  ComputeGate::Slot acquire(ComputeGate& gate);
  std::string preview_png(const Eigen::VectorXd& w, const std::string& key, const std::string& env,
                          const std::string& object, int size);
  nlohmann::json top_weights(const Eigen::VectorXd& w, int count) const;
  /// The automatic exposure of a GI scene with the mean material, computed once per scene.
  double gi_auto_exposure(const std::string& scene, const atlas::GiBasis& basis);
  /// The offered scene named by `scene` (the first when empty); 404 without GI scenes.
  std::string gi_scene(const std::string& scene) const;
  /// The tone map of a GI image: the server's, with `tone` ("" or a curve name) and the exposure
  /// ("auto": the scene's automatic exposure, from `basis` when there is one, else from `image`).
  ToneMap gi_tone(const std::string& scene, bool auto_exposure, double exposure, const std::string& tone,
                  const atlas::GiBasis* basis, const Image* image);

  /// A point or a model material to download (server/export_api.cpp): the request's "x" and
  /// optional "material" (an index: that material's own table).
  struct ExportSubject;
  struct FittedPoint;
  ExportSubject export_subject(const nlohmann::json& body) const;
  BrdfTable subject_table(const ExportSubject& s, ExportStats* stats) const;
  /// The fit of a subject: made once, the last kFitsKept kept (a report, then its files).
  std::shared_ptr<const FittedPoint> fitted(const ExportSubject& s);
  static constexpr std::size_t kFitsKept = 16;
  /// The served model, as a handle whose queries default to the server's mode
  /// (ServerOptions::interpolation): the model itself is shared, never changed.
  const Model model_;
  mutable PointWeights point_weights_{
      [this](const Eigen::VectorXd& x, PointWeights::WarmStart& warm) { return model_.weights(x, warm); }};
  PlausibilityProbe plausibility_;      ///< for one point (weights reply): 4096 sampled columns
  PlausibilityProbe map_plausibility_;  ///< for map cells: 256 sampled columns
  std::shared_ptr<const PreviewSource> previews_;
  ServerOptions options_;
  LatentDomain domain_;
  std::vector<std::string> envs_, objects_;
  std::string model_json_;
  /// GET /api/interpolation's body: made on the first request (2 n^2 numbers), then kept.
  mutable std::once_flag interpolation_once_;
  mutable std::string interpolation_json_;
  ComputeGate compute_;
  ComputeGate heavy_;
  PngCache cache_;
  PreviewGenerations preview_generations_;
  PreviewGenerations gi_generations_;  ///< GET /api/gi per client: stops its refinement
  std::unique_ptr<Realtime> realtime_;
  std::shared_ptr<const GiScenes> gi_;
  std::mutex gi_exposure_mutex_;
  std::map<std::string, double> gi_exposure_;
  std::mutex fits_mutex_;
  std::vector<std::pair<std::string, std::shared_ptr<const FittedPoint>>> fits_;  ///< oldest first
};

}  // namespace matlas::server
