// matlas gi-basis / gi / gi-render: global-illumination images of any map point (docs/GI.md).
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "atlas/gi_basis.h"
#include "atlas/gi_density.h"
#include "atlas/model_material.h"
#include "cli/commands.h"
#include "cli/latent_point.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "core/file_io.h"
#include "manifold/model.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/tracer.h"
#include "pathtrace/world.h"
#include "render/auto_exposure.h"

namespace matlas::cli {

namespace {

struct TraceOptions {
  std::string scene = "floor", object = "sphere", density = "fitted";
  pathtrace::TraceSettings settings;
  /// The settings for `model`: the measured object's density fitted to its database, or the
  /// former fixed lobes (--density fixed).
  pathtrace::TraceSettings for_model(const Model& model) const {
    if (density != "fitted" && density != "fixed") throw Error("--density must be fitted or fixed");
    pathtrace::TraceSettings s = settings;
    s.density = density == "fitted" ? atlas::fit_gi_density(model) : pathtrace::default_fixed_density();
    return s;
  }
};

void add_trace_options(CLI::App& cmd, TraceOptions& o) {
  cmd.add_option("--scene", o.scene, "Built-in scene (floor, box) or a .json scene file")->capture_default_str();
  cmd.add_option("--object", o.object, "The measured object of a built-in scene: sphere, bunny, suzi, teapot or a mesh file")
      ->capture_default_str();
  cmd.add_option("--width", o.settings.width, "Image width")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd.add_option("--height", o.settings.height, "Image height")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd.add_option("--spp", o.settings.spp, "Paths per pixel")->capture_default_str()->check(CLI::Range(1, 1 << 20));
  cmd.add_option("--seed", o.settings.seed, "Random seed")->capture_default_str();
  cmd.add_option("--max-depth", o.settings.max_depth, "Scattering vertices per path")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd.add_option("--density", o.density,
                 "The measured object's sampling density: fitted (to the model's database: no fireflies from sharp "
                 "measured peaks) or fixed (the former lobes, for comparison)")
      ->capture_default_str();
}

struct ImageOptions {
  std::string output;
  RenderOptions tone;  // only --exposure and --tonemap are used
};

void add_image_options(CLI::App& cmd, ImageOptions& o) {
  cmd.add_option("-o,--output", o.output, "Output image: .png (tone mapped sRGB) or .exr (linear)")->required();
  cmd.add_option("--exposure", o.tone.exposure, "PNG exposure in stops")->capture_default_str()->check(finite_number());
  cmd.add_option("--tonemap", o.tone.tonemap, "PNG tone curve: clamp, reinhard or aces")->capture_default_str();
}

/// The files a trace reads besides the model: the scene file, the object's mesh, and the meshes
/// and environment map the scene names (installed names are not files and never match).
std::vector<std::filesystem::path> scene_inputs(const TraceOptions& t, const pathtrace::World& world,
                                                std::vector<std::filesystem::path> others) {
  others.emplace_back(t.scene);
  others.emplace_back(t.object);
  others.emplace_back(world.spec().environment.map);
  for (const auto& object : world.spec().objects) others.emplace_back(object.mesh);
  return others;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// --- gi-basis ---

struct GiBasisArgs {
  std::string model, output, cache;
  int batch = 16;
  TraceOptions trace;
};

void run_gi_basis(const GiBasisArgs& a, const Io& io) {
  const Model model = Model::open(a.model);
  const pathtrace::World world(pathtrace::load_scene(a.trace.scene, a.trace.object));
  refuse_output_among_inputs(a.output, scene_inputs(a.trace, world, {a.model}));
  atlas::GiBasisOptions options;
  options.batch = a.batch;
  options.cache = a.cache.empty() ? std::filesystem::path(a.output + ".cache") : std::filesystem::path(a.cache);
  TerminalProgress progress;
  const auto start = std::chrono::steady_clock::now();
  const atlas::GiBasis basis = atlas::build_gi_basis(model, world, a.trace.for_model(model), options, progress);
  basis.save(a.output);
  print(io.out, "basis of %d material images + P (%dx%d, %d spp) in %.1f s; cache %s\nwrote %s\n", basis.count() + 1,
              basis.width(), basis.height(), a.trace.settings.spp, seconds_since(start), options.cache.c_str(),
              a.output.c_str());
}

void add_gi_basis_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("gi-basis", "Path-trace the GI image basis of a model in a scene (resumable)");
  auto a = std::make_shared<GiBasisArgs>();
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("-o,--output", a->output, "Output basis (.safetensors)")->required();
  cmd->add_option("--cache", a->cache, "Folder of per-material images (default OUTPUT.cache): a rerun resumes");
  cmd->add_option("--batch", a->batch, "Materials traced per pass")->capture_default_str()->check(CLI::Range(1, 1 << 20));
  add_trace_options(*cmd, a->trace);
  cmd->callback([io, a] { run_gi_basis(*a, io); });
}

// --- gi ---

struct GiArgs {
  std::string model, basis, part = "all";
  std::optional<std::string> at, material;
  ImageOptions image;
  bool auto_exposure = false;
};

void run_gi(const GiArgs& a, const Io& io) {
  if (a.part != "all" && a.part != "i1") throw Error("--part must be all or i1");
  refuse_output_among_inputs(a.image.output, {a.model, a.basis});
  const Model model = Model::open(a.model);
  const atlas::GiBasis basis = atlas::GiBasis::load(a.basis);
  atlas::require_basis_of_model(basis, model, a.basis);
  const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
  const Eigen::VectorXd w = model.weights(x);
  const auto start = std::chrono::steady_clock::now();
  const Image image = basis.compose(w, a.part == "i1" ? atlas::GiBasis::Part::i1 : atlas::GiBasis::Part::all);
  const double ms = 1e3 * seconds_since(start);
  ToneMap tone = a.image.tone.tone();
  if (a.auto_exposure) tone.exposure += render::auto_exposure(basis.compose(Eigen::VectorXd::Zero(model.count())));
  write_image(a.image.output, image, tone);
  print(io.out, "composed %dx%d from %d materials in %.1f ms; wrote %s\n", image.width, image.height, basis.count(), ms,
              a.image.output.c_str());
}

void add_gi_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("gi", "The GI image of a map point, composed from a GI basis");
  auto a = std::make_shared<GiArgs>();
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("--basis", a->basis, "GI basis from matlas gi-basis")->required();
  cmd->add_option("--part", a->part, "all (I1 + interpolated I2) or i1")->capture_default_str();
  add_point_options(*cmd, a->at, a->material);
  add_image_options(*cmd, a->image);
  cmd->add_flag("--auto-exposure", a->auto_exposure,
                "Add the scene's automatic exposure (its log-average luminance with the mean material to middle "
                "grey), as the browser's scene view does by default");
  cmd->callback([io, a] { run_gi(*a, io); });
}

// --- gi-render ---

struct RenderArgs {
  std::string model, part = "all";
  std::optional<std::string> at, material;
  TraceOptions trace;
  ImageOptions image;
};

void run_gi_render(const RenderArgs& a, const Io& io) {
  if (a.part != "all" && a.part != "i1" && a.part != "i2" && a.part != "p")
    throw Error("--part must be all, i1, i2 or p");
  const Model model = Model::open(a.model);
  const pathtrace::World world(pathtrace::load_scene(a.trace.scene, a.trace.object));
  refuse_output_among_inputs(a.image.output, scene_inputs(a.trace, world, {a.model}));
  const auto bank = atlas::model_point_bank(model, model.weights(resolve_point(model, a.at, a.material)));
  TerminalProgress progress;
  const auto start = std::chrono::steady_clock::now();
  const pathtrace::TraceImages r = pathtrace::trace(world, bank.get(), a.trace.for_model(model), progress);
  const bool has = !r.once.empty();
  const Image image = a.part == "p" || !has ? r.p : a.part == "i1" ? r.i1(0) : a.part == "i2" ? r.more[0] : r.full(0);
  write_image(a.image.output, image, a.image.tone.tone());
  print(io.out, "traced %dx%d, %d spp in %.1f s; wrote %s\n", image.width, image.height, a.trace.settings.spp,
              seconds_since(start), a.image.output.c_str());
}

void add_gi_render_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("gi-render", "Path-trace a map point's material in a scene (the GI reference)");
  auto a = std::make_shared<RenderArgs>();
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("--part", a->part, "all, i1 (paths touching the object at most once), i2 or p")->capture_default_str();
  add_point_options(*cmd, a->at, a->material);
  add_trace_options(*cmd, a->trace);
  add_image_options(*cmd, a->image);
  cmd->callback([io, a] { run_gi_render(*a, io); });
}

void add_gi_commands(CLI::App& app, const Io& io) {
  add_gi_basis_command(app, io);
  add_gi_command(app, io);
  add_gi_render_command(app, io);
}

}  // namespace

MATLAS_COMMAND(62, add_gi_commands);

}  // namespace matlas::cli
