#include "cli/render_options.h"

#include <sstream>

#include "atlas/gi_density.h"
#include "cli/latent_point.h"
#include "core/error.h"

namespace matlas::cli {

render::SceneDescription RenderOptions::scene_description() const {
  render::SceneDescription d;
  d.object = scene;
  d.environment = env;
  d.environment_rotation = env_rotation;
  d.environment_intensity = env_intensity;
  d.ground = ground;
  d.show_environment = !black_background;
  d.camera.orthographic = ortho;
  d.camera.fov_degrees = fov;
  if (ground) d.camera.position = Vec3(0.0, 0.9, 3.9);
  for (const std::string& text : lights) {
    const Eigen::VectorXd v = parse_point(text, "--light");
    if (v.size() != 3 && v.size() != 4)
      throw Error("--light '" + text + "': expected dx,dy,dz or dx,dy,dz,irradiance");
    const Vec3 dir(v[0], v[1], v[2]);
    if (dir.norm() == 0) throw Error("--light '" + text + "': direction is zero");
    d.lights.push_back({dir.normalized(), Rgb::Constant(v.size() == 4 ? v[3] : 3.0)});
  }
  return d;
}

std::vector<std::filesystem::path> RenderOptions::input_files(std::vector<std::filesystem::path> others) const {
  others.emplace_back(scene);
  others.emplace_back(env);
  return others;
}

render::RenderSettings RenderOptions::settings() const {
  render::RenderSettings s;
  s.width = width;
  s.height = height;
  s.spp = spp;
  s.seed = seed;
  if (sampler == "light-and-lobe") s.sampler = render::Sampler::light_and_lobe;
  else if (sampler == "stratified") s.sampler = render::Sampler::stratified;
  else if (sampler == "independent") s.sampler = render::Sampler::independent;
  else throw Error("--sampler '" + sampler + "': expected light-and-lobe, stratified or independent");
  s.grazing_samples = grazing_samples;
  s.validate();
  return s;
}

ToneMap RenderOptions::tone() const {
  ToneMap t;
  t.exposure = exposure;
  if (tonemap == "clamp") t.curve = ToneMap::Curve::clamp;
  else if (tonemap == "reinhard") t.curve = ToneMap::Curve::reinhard;
  else if (tonemap == "aces") t.curve = ToneMap::Curve::aces;
  else throw Error("--tonemap '" + tonemap + "': expected clamp, reinhard or aces");
  return t;
}

void add_render_options(CLI::App& cmd, RenderOptions& o, bool image) {
  cmd.add_option("--scene", o.scene, "sphere, bunny, suzi, or a .glb/.gltf/.obj file")->capture_default_str();
  cmd.add_option("--env", o.env, "Environment map: installed name (studio, city, ...), .exr/.hdr file, or 'constant'")
      ->capture_default_str();
  cmd.add_option("--env-rotation", o.env_rotation, "Environment rotation about +y, degrees")->check(finite_number());
  cmd.add_option("--env-intensity", o.env_intensity, "Environment radiance scale")->check(finite_number());
  cmd.add_flag("--ground", o.ground, "Put a diffuse ground plane under the object");
  cmd.add_option("--light", o.lights, "Directional light dx,dy,dz[,irradiance] (repeatable)");
  cmd.add_flag("--ortho", o.ortho, "Orthographic camera");
  cmd.add_option("--fov", o.fov, "Vertical field of view of the perspective camera, degrees")->check(finite_number());
  cmd.add_flag("--black-background", o.black_background, "Black instead of the environment behind the object");
  if (!image) return;
  cmd.add_option("--width", o.width, "Image width")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd.add_option("--height", o.height, "Image height")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd.add_option("--spp", o.spp, "Samples per pixel (paths per pixel for the path tracer)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  cmd.add_option("--seed", o.seed, "Random seed (same seed: same samples for every material)");
  cmd.add_option("--sampler", o.sampler,
                 "light-and-lobe (an environment and a material-lobe sample per camera sample), stratified "
                 "(one of them, about 0.55x the time, noisier on glossy materials) or independent")
      ->capture_default_str();
  cmd.add_option("--grazing-samples", o.grazing_samples,
                 "Pixels that see the object at grazing angles take up to this many times a frontal pixel's "
                 "samples, the mean staying --spp (1: --spp everywhere)")
      ->check(CLI::Range(1.0, 64.0))
      ->capture_default_str();
  cmd.add_option("--exposure", o.exposure, "Exposure in stops (PNG output)")->check(finite_number());
  cmd.add_option("--tonemap", o.tonemap, "PNG tone curve: clamp, reinhard or aces")->capture_default_str();
}

pathtrace::TraceSettings PathOptions::settings(const RenderOptions& image, const Model* model) const {
  if (density != "fitted" && density != "fixed") throw Error("--density must be fitted or fixed");
  pathtrace::TraceSettings s;
  s.width = image.width;
  s.height = image.height;
  s.spp = image.spp;
  s.seed = image.seed;
  if (max_depth) s.max_depth = *max_depth;
  s.density = model && density == "fitted" ? atlas::fit_gi_density(*model) : pathtrace::default_fixed_density();
  s.validate();
  return s;
}

void add_path_options(CLI::App& cmd, PathOptions& o) {
  cmd.add_option("--object", o.object,
                 "The measured object of a built-in GI scene (--scene floor or box): sphere, bunny, suzi, teapot or a "
                 "mesh file")
      ->capture_default_str();
  cmd.add_option("--density", o.density,
                 "Path tracer: the measured object's sampling density, fitted (to the model's database, or to a MERL "
                 "file's own table: no fireflies from sharp measured peaks) or fixed (the former lobes, for comparison)")
      ->capture_default_str();
  cmd.add_option("--max-depth", o.max_depth, "Path tracer: scattering vertices per path (8 by default; 1: direct lighting only)")
      ->check(CLI::Range(1, 64));
}

std::set<std::string> given_options(const CLI::App& cmd) {
  std::set<std::string> given;
  for (const CLI::Option* o : cmd.get_options())
    if (o->count() > 0)
      for (const std::string& name : o->get_lnames()) given.insert("--" + name);
  return given;
}

void refuse_options(const std::set<std::string>& given, std::span<const char* const> options, const std::string& what) {
  for (const char* o : options)
    if (given.contains(o)) throw Error(std::string(o) + " does not apply to " + what);
}

}  // namespace matlas::cli
