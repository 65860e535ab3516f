#include "server/api.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <thread>

#include "atlas/map_layers.h"
#include "atlas/material_panels.h"
#include "brdf/brdf_table.h"
#include "brdf/types.h"
#include "core/error.h"
#include "core/parallel.h"
#include "formats/fast_png.h"
#include "formats/merl_file.h"
#include "manifold/export.h"
#include "manifold/interpolation_state.h"
#include "manifold/model_metadata.h"
#include "manifold/project.h"
#include "server/gi_scenes.h"
#include "server/http_error.h"
#include "server/preview_source.h"

namespace matlas::server {

namespace {

nlohmann::json to_json(const Eigen::VectorXd& v) {
  return nlohmann::json(std::vector<double>(v.data(), v.data() + v.size()));
}

/// A square matrix as one array, row-major.
nlohmann::json row_major(const Eigen::MatrixXd& m) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(m.size()));
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) v.push_back(m(r, c));
  return v;
}

/// GET /api/interpolation: the GP's latent points, kernel, nugget taper and Cholesky factor, and
/// the convex mode's metric, so that a client computes Model::weights itself (docs/API.md).
std::string interpolation_json(const Model& model) {
  const InterpolationState state = interpolation_state(model);
  nlohmann::json latent = nlohmann::json::array();
  for (Eigen::Index i = 0; i < state.latent.rows(); ++i) latent.push_back(to_json(state.latent.row(i).transpose()));
  return nlohmann::json{{"mode", std::string(to_string(model.interpolation()))},
                        {"lengthscale", state.lengthscale},
                        {"nugget", state.nugget},
                        {"latent", latent},
                        {"taper_radius", to_json(state.taper_radius)},
                        {"cholesky", row_major(state.cholesky_lower)},
                        {"metric", row_major(state.convex_metric)}}
      .dump();
}

}  // namespace

void Api::add_refinement_headers(Reply& r, const render::RefinementState& state, bool interrupted) {
  char error[32], secs[32];
  std::snprintf(error, sizeof error, "%.6g", state.relative_error);
  std::snprintf(secs, sizeof secs, "%.3f", state.seconds);
  r.headers.emplace_back("Cache-Control", "no-store");
  r.headers.emplace_back("X-Matlas-Spp", std::to_string(state.spp));
  r.headers.emplace_back("X-Matlas-Error", std::isfinite(state.relative_error) ? error : "unknown");
  r.headers.emplace_back("X-Matlas-Converged", state.converged ? "1" : "0");
  r.headers.emplace_back("X-Matlas-Seconds", secs);
  if (interrupted) r.headers.emplace_back("X-Matlas-Interrupted", "1");
}

void Api::add_denoised_headers(Reply& r, bool denoised, double denoised_error) {
  if (!denoised) return;
  char error[32];
  std::snprintf(error, sizeof error, "%.6g", denoised_error);
  r.headers.emplace_back("X-Matlas-Denoised", "1");
  r.headers.emplace_back("X-Matlas-Denoised-Error", error);
}

std::string Api::point_key(const Eigen::VectorXd& x) {
  std::string key;
  char buf[32];
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%.17g,", x[i]);
    key += buf;
  }
  return key;
}

Reply Reply::json(const nlohmann::json& j) {
  Reply r;
  r.body = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return r;
}

Reply Reply::bytes(std::string data, std::string content_type) {
  Reply r;
  r.body = std::move(data);
  r.content_type = std::move(content_type);
  return r;
}

Api::Api(const Model& model, std::shared_ptr<const PreviewSource> previews, const ServerOptions& options)
    : model_(model.with_interpolation(options.interpolation.value_or(model.interpolation()))),
      plausibility_(model_, 4096),
      map_plausibility_(model_, 256),
      previews_(std::move(previews)),
      options_(options),
      domain_(LatentDomain::around(model.latent_min(), model.latent_max(), options.domain_margin)),
      envs_(previews_->environments()),
      objects_(previews_->objects()),
      compute_(ComputeGate::Options{options.compute_slots > 0
                                        ? options.compute_slots
                                        : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
                                    4 * options.waiting_per_client}),  // light work: a page sends several at once
      heavy_(ComputeGate::Options{options.heavy_slots, options.waiting_per_client}),
      cache_(options.cache_entries),
      realtime_(std::make_unique<Realtime>(model, envs_, objects_)),
      gi_(options.gi_scenes ? options.gi_scenes(model) : nullptr) {
  nlohmann::json j;
  j["name"] = model_name(model);
  j["count"] = model.count();
  j["dim"] = model.dim();
  j["names"] = model.names();
  nlohmann::json latent = nlohmann::json::array(), colors = nlohmann::json::array();
  for (int i = 0; i < model.count(); ++i) {
    latent.push_back(to_json(model.latent().row(i).transpose()));
    nlohmann::json rgb = nlohmann::json::array();
    for (int c = 0; c < 3; ++c) {
      const double a = std::clamp(model.material_albedo()(i, c), 0.0, 1.0);
      rgb.push_back(std::lround(255.0 * srgb_encode(static_cast<float>(a))));
    }
    colors.push_back(rgb);
  }
  j["latent"] = latent;
  j["colors"] = colors;
  j["bounds"] = {{"min", to_json(model.latent_min())}, {"max", to_json(model.latent_max())}};
  j["domain"] = {{"min", to_json(domain_.lo)}, {"max", to_json(domain_.hi)}};
  j["dims"] = {model.dims().theta_h, model.dims().theta_d, model.dims().phi_d};
  j["scenes"] = {{"envs", envs_},
                 {"objects", objects_},
                 {"default_env", previews_->default_environment()},
                 {"default_object", previews_->default_object()}};
  j["preview"] = {{"size", previews_->size()}, {"drag_size", previews_->drag_size()}, {"max_size", 512}};
  j["layers"] = {"albedo", "variance", "plausibility"};
  // How m(x) is made from the inputs: "gp" (the paper's GP weights) or "convex" (non-negative
  // weights summing to 1); models without the field predate the choice and are "gp".
  j["interpolation"] = std::string(to_string(model_.interpolation()));  // the server's mode
  j["uncertainty"] = {{"fade_from", atlas::kFadeFrom}, {"fade_to", atlas::kFadeTo}};
  j["plausible_everywhere"] = atlas::plausible_by_construction(model_, &map_plausibility_);
  j["albedo_angles"] = kAlbedoAngles;
  if (gi_) j["gi"] = {{"scenes", gi_->scenes()}, {"preloaded", gi_->preloaded()}, {"views", gi_->views()}};
  model_json_ = j.dump();
}

ComputeGate::Slot Api::acquire(ComputeGate& gate) {
  ComputeGate::Refusal why = ComputeGate::Refusal::kNone;
  ComputeGate::Slot slot = gate.acquire(options_.queue_timeout, request_client(), &why);
  if (why == ComputeGate::Refusal::kRefused)
    throw HttpError(503, "this client has " + std::to_string(options_.waiting_per_client) +
                             " requests of this kind waiting already; try again when one is answered");
  if (!slot) throw HttpError(503, "the server is busy; try again");
  return slot;
}

Reply Api::model_info() const { return Reply::bytes(model_json_, "application/json"); }

Reply Api::interpolation() const {
  std::call_once(interpolation_once_, [this] { interpolation_json_ = interpolation_json(model_); });
  return Reply::bytes(interpolation_json_, "application/json");
}

std::string Api::preview_png(const Eigen::VectorXd& w, const std::string& key, const std::string& env,
                             const std::string& object, int size) {
  const std::string full_key = key + "|" + env + "|" + object + "|" + std::to_string(size);
  if (auto hit = cache_.get(full_key)) return *hit;
  std::string png;
  {
    auto slot = acquire(compute_);
    png = encode_png_fast(previews_->render(w, env, object, size), previews_->tone());
  }
  cache_.put(full_key, png);
  return png;
}

Reply Api::preview(const std::string& body) {
  preview_generations_.advance(request_client());
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const std::string env = parse_choice(j, "env", envs_, previews_->default_environment());
  const std::string object = parse_choice(j, "object", objects_, previews_->default_object());
  const int size = parse_int(j, "size", 16, 512, previews_->size());
  Reply r = Reply::bytes(preview_png(weights_at(x), point_key(x).insert(0, 1, 'x'), env, object, size), kPng);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Reply Api::preview_status(const std::string& env_text, const std::string& object_text) const {
  const nlohmann::json j = {{"env", env_text.empty() ? nlohmann::json() : nlohmann::json(env_text)},
                            {"object", object_text.empty() ? nlohmann::json() : nlohmann::json(object_text)}};
  const std::string env = parse_choice(j, "env", envs_, previews_->default_environment());
  const std::string object = parse_choice(j, "object", objects_, previews_->default_object());
  const PreviewSource::SceneStatus s = previews_->status(env, object);
  nlohmann::json reply = {{"env", env}, {"object", object}, {"ready", s.ready}, {"progress", s.progress},
                          {"stage", s.stage}, {"seconds", s.seconds}};
  if (s.seconds_left >= 0) reply["seconds_left"] = s.seconds_left;
  if (!s.error.empty()) reply["error"] = s.error;
  Reply r = Reply::json(reply);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Reply Api::preview_refine(const std::string& body) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const std::string env = parse_choice(j, "env", envs_, previews_->default_environment());
  const std::string object = parse_choice(j, "object", objects_, previews_->default_object());
  const double seconds = parse_number(j, "seconds", 0.05, 5.0, 0.5);
  const bool denoise = parse_flag(j, "denoise", false);
  // A newer preview or map layer request from the same client (the pointer moved, the scene's
  // basis image arrived, the map asks for a layer) stops the pass under way: the answer is the
  // refinement as it was, marked X-Matlas-Interrupted (200: an expected event, not an error).
  const std::string client = request_client();
  SupersededSink superseded(preview_generations_, client, preview_generations_.current(client));
  PreviewSource::Refined refined;
  {
    auto slot = acquire(compute_);
    refined = previews_->refine(weights_at(x), point_key(x), env, object, seconds, denoise, superseded);
  }
  Reply r = Reply::bytes(encode_png_fast(refined.image, previews_->tone()), kPng);
  add_refinement_headers(r, refined.state, refined.interrupted);
  add_denoised_headers(r, refined.denoised, refined.denoised_error);
  return r;
}

Reply Api::thumbnail(int index, const std::string& env, const std::string& object, int size) {
  if (index < 0 || index >= model_.count())
    throw HttpError(404, "no material " + std::to_string(index) + " (the model has " +
                             std::to_string(model_.count()) + ")");
  const nlohmann::json j = {{"env", env.empty() ? nlohmann::json() : nlohmann::json(env)},
                            {"object", object.empty() ? nlohmann::json() : nlohmann::json(object)}};
  const std::string e = parse_choice(j, "env", envs_, previews_->default_environment());
  const std::string o = parse_choice(j, "object", objects_, previews_->default_object());
  Reply r = Reply::bytes(
      preview_png(model_.material_weights(index), std::to_string(index).insert(0, 1, 'm'), e, o, size), kPng);
  r.headers.emplace_back("Cache-Control", "max-age=3600");
  return r;
}

nlohmann::json Api::top_weights(const Eigen::VectorXd& w, int count) const {
  std::vector<int> order(static_cast<std::size_t>(w.size()));
  std::iota(order.begin(), order.end(), 0);
  const auto k = static_cast<std::size_t>(std::min<Eigen::Index>(count, w.size()));
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](int a, int b) { return std::abs(w[a]) > std::abs(w[b]); });
  nlohmann::json top = nlohmann::json::array();
  for (std::size_t i = 0; i < k; ++i)
    top.push_back({{"index", order[i]}, {"name", model_.names()[static_cast<std::size_t>(order[i])]},
                   {"weight", w[order[i]]}});
  return top;
}

Reply Api::weights(const std::string& body) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const int top = parse_int(j, "top", 0, model_.count(), std::min(8, model_.count()));
  const Eigen::VectorXd w = weights_at(x);
  const Plausibility p = plausibility_(w);
  return Reply::json({{"x", to_json(x)}, {"weights", to_json(w)}, {"variance", model_.variance(x)},
                      {"top", top_weights(w, top)},
                      {"plausibility",
                       {{"negative_fraction", p.negative_fraction},
                        {"max_albedo", p.max_albedo},
                        {"min_albedo", p.min_albedo},
                        {"sampled_values", plausibility_.samples()},
                        {"plausible", p.violation() == 0.0}}}});
}

Reply Api::slice(const std::string& body) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const double phi_d = parse_number(j, "phi_d", 0.0, 180.0, 90.0);
  double vmax = 0;
  std::string png;
  {
    auto slot = acquire(compute_);
    png = atlas::slice_png(model_, weights_at(x), phi_d, &vmax);
  }
  Reply r = Reply::bytes(std::move(png), kPng);
  r.headers.emplace_back("X-Matlas-Max", std::to_string(vmax));
  return r;
}

Reply Api::lobe(const std::string& body) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const double theta_i = parse_number(j, "theta_i", 0.0, 89.0, 30.0);
  const int samples = parse_int(j, "samples", 8, 721, 181);
  const atlas::Lobe lobe = atlas::incidence_plane_lobe(model_, weights_at(x), theta_i, samples);
  nlohmann::json rgb = nlohmann::json::array();
  for (const Rgb& v : lobe.value) rgb.push_back({v[0], v[1], v[2]});
  return Reply::json({{"theta_i", theta_i}, {"theta_o", lobe.theta_o_degrees}, {"rgb", rgb}});
}

Reply Api::albedo(const std::string& body) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const auto curve = model_.albedo_curve(weights_at(x));
  nlohmann::json rgb = nlohmann::json::array();
  for (const Rgb& v : curve) rgb.push_back({v[0], v[1], v[2]});
  return Reply::json({{"theta_o", atlas::albedo_angles_degrees()}, {"rgb", rgb}});
}

Reply Api::map_layer(const std::string& body) {
  const auto j = parse_json_object(body);
  const atlas::MapLayer layer =
      atlas::map_layer_from_name(parse_choice(j, "layer", {"albedo", "variance", "plausibility"}, "albedo"), "layer");
  const Eigen::VectorXd base = parse_latent(j, "x", domain_);
  int axis_x = 0, axis_y = 1;
  const int q = model_.dim();
  if (q < 2) throw bad_request("map layers need a latent space of at least 2 dimensions");
  if (j.contains("axes")) {
    const auto& axes = j["axes"];
    if (!axes.is_array() || axes.size() != 2) throw bad_request("\"axes\" must be two integers");
    axis_x = parse_int_value(axes[0], "\"axes\"[0]", 0, q - 1);
    axis_y = parse_int_value(axes[1], "\"axes\"[1]", 0, q - 1);
    if (axis_x == axis_y)
      throw bad_request("\"axes\" must be two different axes in [0, " + std::to_string(q - 1) + "]");
  }
  if (!j.contains("rect") || !j["rect"].is_array() || j["rect"].size() != 4)
    throw bad_request("\"rect\" must be [x0, x1, y0, y1]");
  double rect[4];
  for (int i = 0; i < 4; ++i) {
    const auto& v = j["rect"][static_cast<std::size_t>(i)];
    if (!v.is_number() || !std::isfinite(v.get<double>()) || std::abs(v.get<double>()) > 1e6)
      throw bad_request("\"rect\" values must be finite numbers of magnitude at most 1e6");
    rect[i] = v.get<double>();
  }
  if (!(rect[0] < rect[1] && rect[2] < rect[3])) throw bad_request("\"rect\" must have x0 < x1 and y0 < y1");
  int width = 64, height = 64;
  if (j.contains("size")) {
    const auto& s = j["size"];
    if (!s.is_array() || s.size() != 2) throw bad_request("\"size\" must be [width, height]");
    width = parse_int_value(s[0], "\"size\"[0] (width)", 4, 256);
    height = parse_int_value(s[1], "\"size\"[1] (height)", 4, 256);
  }
  // The page pauses its refinement at rest while a layer is on its way; the pass under way stops
  // too, so that the layer has the cores (as a newer preview request stops it).
  preview_generations_.advance(request_client());
  auto slot = acquire(heavy_);
  const auto plane = atlas::LatentPlane::rectangle(base, axis_x, axis_y, rect[0], rect[1], rect[2], rect[3]);
  return Reply::bytes(atlas::map_layer_png(model_, plane, width, height, layer, &map_plausibility_), kPng);
}

Reply Api::project(const std::string& file_bytes) {
  if (file_bytes.empty()) throw bad_request("the upload is empty: send a MERL .binary file as the body");
  BrdfTable table;
  try {
    table = decode_merl(file_bytes, "upload");
  } catch (const Error& e) {
    std::string message = e.what();
    const std::string prefix = "upload: ";
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
    throw HttpError(422, "the upload is not a valid MERL .binary file: " + message);
  }
  if (!(table.dims() == model_.dims()))
    throw HttpError(422, "the upload's grid is " + table.dims().to_string() + " but the model's is " +
                             model_.dims().to_string());
  Projection p;
  {
    auto slot = acquire(heavy_);
    try {
      p = project_material(model_, table);
    } catch (const HttpError&) {
      throw;
    } catch (const Error& e) {
      throw HttpError(422, std::string("the upload cannot be projected: ") + e.what());
    }
  }
  nlohmann::json nearest = nullptr;
  if (p.nearest >= 0)
    nearest = {{"index", p.nearest}, {"name", model_.names()[static_cast<std::size_t>(p.nearest)]},
               {"residual", p.nearest_relative_error}};
  return Reply::json({{"x", to_json(p.x)},
                      {"residual", p.relative_error},
                      {"variance", p.variance},
                      {"nearest", nearest},
                      {"missing", p.missing},
                      {"top", top_weights(model_.weights(p.x), 8)}});
}

Reply Api::realtime_info() { return Reply::json(realtime_->info()); }

Reply Api::realtime_coefficients() {
  Reply r = Reply::bytes(realtime_->coefficients(), "application/octet-stream");
  r.headers.emplace_back("Cache-Control", "no-cache");
  return r;
}

Reply Api::realtime_environment(const std::string& name) {
  auto [shape, atlas] = realtime_->environment(name);
  Reply r = Reply::bytes(*atlas, "application/octet-stream");
  r.headers.emplace_back("X-Matlas-Shape", shape.dump());
  r.headers.emplace_back("Cache-Control", "max-age=3600");
  return r;
}

Reply Api::realtime_mesh(const std::string& name) { return Reply::bytes(realtime_->mesh(name), "application/octet-stream"); }

Reply Api::realtime_lights(const std::string& body) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  Reply r = Reply::bytes(realtime_->light_table(weights_at(x)), "application/octet-stream");
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Reply Api::realtime_reference(const std::string& body) { return reference_reply(body, false); }

Reply Api::realtime_reference_radiance(const std::string& body) { return reference_reply(body, true); }

Reply Api::reference_reply(const std::string& body, bool radiance) {
  const auto j = parse_json_object(body);
  const Eigen::VectorXd x = parse_latent(j, "x", domain_);
  const std::string env = parse_choice(j, "env", envs_, previews_->default_environment());
  const double rotation = parse_number(j, "rotation", -360.0, 360.0, 0.0);
  const double exposure = parse_number(j, "exposure", -16.0, 16.0, 0.0);
  const int size = parse_int(j, "size", 16, 512, 256);
  auto slot = acquire(heavy_);
  Reply r = radiance ? Reply::bytes(realtime_->reference_radiance(weights_at(x), env, rotation, exposure, size),
                                    "application/octet-stream")
                     : Reply::bytes(realtime_->reference_png(weights_at(x), env, rotation, exposure, size), kPng);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace matlas::server
