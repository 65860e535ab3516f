// The scene-view endpoints of the API (docs/API.md): GET /api/gi composes the GI image of a point
// from the scene's basis, POST /api/gi/refine traces the point itself while the pointer rests;
// the tone map (exposure, automatic exposure once per scene, tone curve) of both.
#include <cmath>
#include <cstdio>
#include <string>

#include "atlas/gi_basis.h"
#include "formats/fast_png.h"
#include "render/auto_exposure.h"
#include "render/firefly_filter.h"
#include "server/api.h"
#include "server/gi_scenes.h"
#include "server/http_error.h"

namespace matlas::server {

double Api::gi_auto_exposure(const std::string& scene, const atlas::GiBasis& basis) {
  std::lock_guard lock(gi_exposure_mutex_);
  const auto it = gi_exposure_.find(scene);
  if (it != gi_exposure_.end()) return it->second;
  // The scene with the model's mean material (w = 0): one exposure for the whole map, so that
  // dragging changes the material, not the brightness of the room.
  const double e = render::auto_exposure(basis.compose(Eigen::VectorXd::Zero(model_.count())));
  gi_exposure_.emplace(scene, e);
  return e;
}

std::string Api::gi_scene(const std::string& scene) const {
  if (!gi_ || gi_->scenes().empty())
    throw HttpError(404, "this server has no GI scenes: start it with --gi-basis FILE (from matlas gi-basis) "
                         "or --gi-scenes floor,box");
  return scene.empty() ? gi_->scenes().front() : scene;
}

ToneMap Api::gi_tone(const std::string& scene, bool auto_exposure, double exposure, const std::string& tone_text,
                     const atlas::GiBasis* basis, const Image* image) {
  ToneMap tone = gi_->tone();
  if (tone_text == "aces") tone.curve = ToneMap::Curve::aces;
  else if (tone_text == "reinhard") tone.curve = ToneMap::Curve::reinhard;
  else if (tone_text == "clamp") tone.curve = ToneMap::Curve::clamp;
  else if (!tone_text.empty()) throw bad_request("tone must be aces, reinhard or clamp, got " + quoted_excerpt(tone_text));
  if (!auto_exposure) tone.exposure += exposure;
  else if (basis) tone.exposure += gi_auto_exposure(scene, *basis);
  else if (image) tone.exposure += render::auto_exposure(*image);
  return tone;
}

Reply Api::gi(const std::string& scene_text, const std::string& x_text, const std::string& exposure_text,
              const std::string& tone_text) {
  const std::string scene = gi_scene(scene_text);
  gi_generations_.advance(request_client());  // the pointer moved: a refinement under way stops
  const Eigen::VectorXd x = parse_latent_text(x_text, "x", domain_);
  const bool auto_exposure = exposure_text == "auto";
  const double exposure = exposure_text.empty() || auto_exposure ? 0.0 : parse_number_text(exposure_text, "exposure", -16.0, 16.0);
  const GiSceneState state = gi_->state(scene);  // matlas::Error (400) naming the offered scenes
  if (!state.error.empty()) throw HttpError(500, "the GI scene '" + scene + "' could not be traced: " + state.error);
  if (!state.basis) {
    char percent[16];
    std::snprintf(percent, sizeof percent, "%.0f %%", 100.0 * state.progress);
    Reply r = Reply::json({{"error", "the GI scene '" + scene + "' is being prepared (" + state.stage + ": " + percent +
                                         "); try again in a few seconds"}});
    r.status = 503;
    r.headers.emplace_back("Retry-After", "2");
    r.headers.emplace_back("X-Matlas-Progress", std::to_string(state.progress));
    return r;
  }
  std::string png;
  ToneMap tone;
  int fireflies = 0;
  {
    auto slot = acquire(compute_);
    tone = gi_tone(scene, auto_exposure, exposure, tone_text, state.basis.get(), nullptr);
    // The drag's image, shown until the refinement at rest replaces it: its fireflies removed
    // (render/firefly_filter.h: biased, said in a header).
    Image image = state.basis->compose(weights_at(x));
    fireflies = render::remove_fireflies(image);
    png = encode_png_fast(image, tone);
  }
  Reply r = Reply::bytes(std::move(png), kPng);
  r.headers.emplace_back("Cache-Control", "no-store");
  r.headers.emplace_back("X-Matlas-Fireflies", std::to_string(fireflies));
  char used[32];
  std::snprintf(used, sizeof used, "%.3f", tone.exposure);
  r.headers.emplace_back("X-Matlas-Exposure", used);
  return r;
}

Reply Api::gi_refine(const std::string& body) {
  const auto j = parse_json_object(body);
  const std::string scene = gi_scene(j.contains("scene") && j["scene"].is_string() ? j["scene"].get<std::string>() : "");
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const double seconds = parse_number(j, "seconds", 0.05, 5.0, 0.5);
  const bool denoise = parse_flag(j, "denoise", false);
  const bool auto_exposure = j.contains("exposure") && j["exposure"].is_string() && j["exposure"].get<std::string>() == "auto";
  const double exposure = auto_exposure ? 0.0 : parse_number(j, "exposure", -16.0, 16.0, 0.0);
  std::string tone_text;
  if (j.contains("tone")) {
    if (!j["tone"].is_string()) throw bad_request("tone must be a string");
    tone_text = j["tone"].get<std::string>();
  }
  const GiSceneState state = gi_->state(scene);  // matlas::Error (400) naming the offered scenes
  // A GET /api/gi from the same client (the pointer moved) stops the pass under way: the answer
  // is the refinement as it was, marked X-Matlas-Interrupted (200: expected, not an error).
  const std::string client = request_client();
  SupersededSink superseded(gi_generations_, client, gi_generations_.current(client));
  GiScenes::Refined refined;
  bool interrupted = false;
  {
    auto slot = acquire(compute_);
    try {
      refined = gi_->refine(scene, weights_at(x), point_key(x), seconds, denoise, superseded);
    } catch (const PreviewSource::Interrupt&) {
      interrupted = true;
      if (auto r = gi_->refined(scene, point_key(x), denoise)) refined = std::move(*r);
    }
  }
  const ToneMap tone = gi_tone(scene, auto_exposure, exposure, tone_text, state.basis.get(),
                               refined.state.spp > 0 ? &refined.image : nullptr);
  Reply r = Reply::bytes(refined.state.spp > 0 ? encode_png_fast(refined.image, tone) : std::string(), kPng);
  if (refined.state.spp == 0) r = Reply::json({{"spp", 0}});
  add_refinement_headers(r, refined.state, interrupted);
  add_denoised_headers(r, refined.denoised, refined.denoised_error);
  char used[32];
  std::snprintf(used, sizeof used, "%.3f", tone.exposure);
  r.headers.emplace_back("X-Matlas-Exposure", used);
  return r;
}

}  // namespace matlas::server
