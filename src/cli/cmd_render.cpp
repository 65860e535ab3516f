// matlas render: one picture of a material (a MERL .binary file, a model point, or the analytic
// model of a fit report from `matlas fit`), by one of the integrators over one of the scenes, or
// composed from a basis:
// - the previews' scene (--scene sphere, bunny, suzi or a mesh: an object under an environment)
//   by their direct lighting (--integrator direct) or by the path tracer (--integrator path);
// - a GI scene (--scene floor, box, NAME@VIEW or a .json file) by the path tracer, any part of
//   its image (--part all, i1, i2, p);
// - a basis (--basis: an image basis from `matlas basis`, a GI basis from `matlas basis --scene
//   floor`) composed at the point.
// `gi-render` (a GI scene) and `gi` (a GI basis) are its former names, kept as deprecated aliases
// with their former defaults.
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "artist/fit_report.h"
#include "atlas/gi_basis.h"
#include "atlas/gi_density.h"
#include "atlas/model_basis.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "cli/commands.h"
#include "cli/latent_point.h"
#include "cli/print.h"
#include "cli/render_options.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/merl_file.h"
#include "formats/safetensors.h"
#include "manifold/model.h"
#include "pathtrace/preview_scene.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/tracer.h"
#include "pathtrace/world.h"
#include "render/auto_exposure.h"
#include "render/firefly_filter.h"
#include "render/image_basis.h"
#include "render/material.h"
#include "render/progressive_render.h"
#include "render/render.h"

namespace matlas::cli {

namespace {

struct RenderArgs {
  std::string input, output, integrator = "direct", part = "all";
  std::optional<std::string> at, material, basis;
  std::optional<double> target_error;
  bool auto_exposure = false, remove_fireflies = false;
  RenderOptions options;
  PathOptions path;
  std::set<std::string> given;  ///< the options given on the command line
};

bool is_merl(const std::string& path) {
  return path.size() > 7 && path.compare(path.size() - 7, 7, ".binary") == 0;
}

/// A fit report (`matlas fit -o X.json`): the fitted analytic model is rendered, not a table of it.
bool is_fit_report(const std::string& path) {
  return path.size() > 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

/// A material of its own, not a model's: a MERL table (nearest-bin lookups; the material keeps
/// its table) or the analytic model of a fit report.
std::shared_ptr<const render::Material> file_material(const RenderArgs& a) {
  if (a.at || a.material) throw Error("--at/--material apply to models, not to the file " + a.input);
  if (is_fit_report(a.input)) {
    nlohmann::json report;
    try {
      report = nlohmann::json::parse(read_file(a.input));
    } catch (const nlohmann::json::exception& e) {
      throw Error(a.input + ": not JSON (" + e.what() + ")");
    }
    return std::make_shared<const render::FunctionMaterial>(artist::fitted_brdf(report, a.input));
  }
  auto table = std::make_shared<const BrdfTable>(read_merl(a.input));
  auto lookup = std::make_shared<const render::TableMaterial>(*table);
  return std::shared_ptr<const render::Material>(lookup.get(), [lookup, table](const render::Material*) {});
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// The weights of the point given (--at, or a database material's own weights).
Eigen::VectorXd point_weights(const RenderArgs& a, const Model& model) {
  const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
  return a.material ? model.material_weights(model.index_of(*a.material)) : model.weights(x);
}

/// A part of a traced image: all, i1 (paths touching the object at most once), i2 or p.
Image part_of(const pathtrace::TraceImages& r, const std::string& part) {
  if (part == "p" || r.once.empty()) return r.p;
  return part == "i1" ? r.i1(0) : part == "i2" ? r.more[0] : r.full(0);
}

/// The files a trace reads besides the input: the scene file, the object's mesh, and the meshes
/// and environment map the scene names (installed names are not files and never match).
std::vector<std::filesystem::path> scene_inputs(const RenderArgs& a, const pathtrace::World& world) {
  std::vector<std::filesystem::path> inputs{a.input, a.options.scene, a.path.object, world.spec().environment.map};
  for (const auto& object : world.spec().objects) inputs.emplace_back(object.mesh);
  return inputs;
}

/// The path tracer over `world` for the input (a MERL table, or the model at the point: in a GI
/// scene as the GI bases see it, extrapolations' negative values kept, so that it is their
/// reference; in the previews' scene as a table built once, as the previews render it).
Image trace_input(const RenderArgs& a, const pathtrace::World& world, bool gi_scene, ProgressSink& progress,
                  render::RenderStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  pathtrace::TraceImages r;
  pathtrace::TraceSettings settings;
  if (is_merl(a.input) || is_fit_report(a.input)) {
    const std::shared_ptr<const render::Material> material = file_material(a);
    const render::MaterialList bank({material.get()});
    settings = a.path.settings(a.options, nullptr);
    if (a.path.density == "fitted") settings.density = atlas::fit_gi_density(bank);  // its own lobes
    r = pathtrace::trace(world, &bank, settings, progress);
  } else {
    const Model model = Model::open(a.input);
    const Eigen::VectorXd w = point_weights(a, model);
    settings = a.path.settings(a.options, &model);
    if (gi_scene) {
      r = pathtrace::trace(world, atlas::model_point_bank(model, w).get(), settings, progress);
    } else {
      const atlas::ModelTableMaterial material(model, w);
      const render::MaterialList bank({&material});
      r = pathtrace::trace(world, &bank, settings, progress);
    }
  }
  stats.seconds = seconds_since(start);
  stats.camera_samples = static_cast<std::uint64_t>(settings.width) * static_cast<std::uint64_t>(settings.height) *
                         static_cast<std::uint64_t>(settings.spp);
  return part_of(r, a.part);
}

/// --target-error: the refinement of the previews at rest (render/progressive_render.h: passes
/// until the estimated relative RMS error inside the object is at most the target, adaptive
/// sampling), --spp samples per pixel at most (4096 when not given).
Image refine_to_target(const RenderArgs& a, std::shared_ptr<const render::Scene> scene,
                       std::shared_ptr<const render::Material> material, const render::RenderSettings& settings,
                       ProgressSink& progress, render::RenderStats& stats, render::RefinementState& refined) {
  if (!(*a.target_error > 0) || !(*a.target_error < 1))
    throw Error("--target-error must be in (0, 1) (a relative RMS error, e.g. 0.01), got " + std::to_string(*a.target_error));
  render::ProgressiveSettings ps;
  ps.render = settings;
  ps.limits.max_spp = a.given.contains("--spp") ? settings.spp : 4096;
  ps.render.spp = std::min(16, ps.limits.max_spp);
  ps.limits.target_error = *a.target_error;
  ps.limits.min_converged_spp = std::min(64, ps.limits.max_spp);
  ps.limits.max_pass_spp = 256;
  ps.shown = a.options.tone();
  render::ProgressiveRender refinement(std::move(scene), std::move(material), ps);
  while (!(refined = refinement.refine(1.0, progress)).converged) {
  }
  stats.seconds = refined.seconds;
  stats.camera_samples = static_cast<std::uint64_t>(refined.spp) * static_cast<std::uint64_t>(settings.width) *
                         static_cast<std::uint64_t>(settings.height);
  return refinement.image();
}

/// The previews' scene: direct lighting (render::render) or the path tracer over the same scene.
Image render_preview_scene(const RenderArgs& a, ProgressSink& progress, render::RenderStats& stats,
                           std::optional<render::RefinementState>& refined) {
  const bool path = a.integrator == "path";
  refuse_options(a.given, std::array{"--object"}, "the previews' scene (--scene names its object)");
  if (!path) refuse_options(a.given, std::array{"--max-depth", "--density", "--part"}, "--integrator direct");
  if (path) refuse_options(a.given, std::array{"--target-error"}, "--integrator path (a fixed --spp)");
  refuse_output_among_inputs(a.output, a.options.input_files({a.input}));
  if (path) {
    const pathtrace::World world(pathtrace::preview_scene(a.options.scene_description()));
    return trace_input(a, world, false, progress, stats);
  }
  const auto scene = std::make_shared<const render::Scene>(a.options.scene_description());
  render::RenderSettings settings = a.options.settings();
  std::shared_ptr<const render::Material> material;
  if (is_merl(a.input) || is_fit_report(a.input)) {
    material = file_material(a);
  } else {
    const Model model = Model::open(a.input);
    const Eigen::VectorXd w = point_weights(a, model);
    // The model's fitted mixture (the same samples as its bases). The table of m(w) is built
    // once: a render's millions of lookups then read one value per channel, not a dot product of n.
    material = std::make_shared<const atlas::ModelTableMaterial>(model, w);
    settings = atlas::model_render_settings(model, settings);
  }
  if (!a.target_error) return render::render(*scene, *material, settings, progress, &stats);
  return refine_to_target(a, scene, material, settings, progress, stats, refined.emplace());
}

/// A GI scene (floor, box, a view of one, a .json file): the path tracer.
Image render_gi_scene(const RenderArgs& a, ProgressSink& progress, render::RenderStats& stats) {
  refuse_options(a.given, kPreviewSceneOptions,
                 "a GI scene (--scene " + a.options.scene + ": it says its own lights, camera and environment)");
  refuse_options(a.given, std::array{"--target-error"}, "a GI scene (a fixed --spp)");
  if (a.given.contains("--integrator") && a.integrator != "path")
    throw Error("--integrator " + a.integrator + ": a GI scene (--scene " + a.options.scene + ") is path-traced");
  const pathtrace::World world(pathtrace::load_scene(a.options.scene, a.path.object));
  refuse_output_among_inputs(a.output, scene_inputs(a, world));
  return trace_input(a, world, true, progress, stats);
}

/// Whether `path` holds a GI basis (else an image basis, or not a basis: ImageBasis::open says).
bool is_gi_basis(const std::string& path) {
  try {
    const SafetensorsFile f = SafetensorsFile::open(path);
    const auto it = f.metadata().find("format");
    return it != f.metadata().end() && it->second == "matlas-gi-basis";
  } catch (const Error&) {
    return false;
  }
}

/// --basis: the basis composed at the point (the previews' instant image, or the scene view's).
void compose_basis(const RenderArgs& a, const Io& io) {
  static constexpr const char* kRenderOptions[] = {"--scene", "--integrator", "--width", "--height", "--spp",
                                                   "--seed", "--object", "--density", "--max-depth"};
  refuse_options(a.given, kRenderOptions, "--basis (the basis was rendered with its own)");
  refuse_options(a.given, std::array{"--target-error"}, "--basis (a composed image is not refined)");
  refuse_options(a.given, kPreviewSceneOptions, "--basis (the basis was rendered with its own)");
  if (is_merl(a.input) || is_fit_report(a.input)) throw Error("--basis composes a model's basis, not the file " + a.input);
  refuse_output_among_inputs(a.output, {a.input, *a.basis});
  const Model model = Model::open(a.input);
  const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
  const Eigen::VectorXd w = model.weights(x);
  ToneMap tone = a.options.tone();
  // The basis's composition at weights, and the image its automatic exposure is keyed to (the
  // mean material's, the whole GI image).
  std::optional<atlas::GiBasis> gi;
  std::optional<render::ImageBasis> previews;
  std::function<Image(const Eigen::VectorXd&)> compose, key;
  if (is_gi_basis(*a.basis)) {
    if (a.part != "all" && a.part != "i1") throw Error("--part must be all or i1 for a GI basis");
    gi.emplace(atlas::GiBasis::load(*a.basis));
    atlas::require_basis_of_model(*gi, model, *a.basis);
    const auto part = a.part == "i1" ? atlas::GiBasis::Part::i1 : atlas::GiBasis::Part::all;
    compose = [&, part](const Eigen::VectorXd& v) { return gi->compose(v, part); };
    key = [&](const Eigen::VectorXd& v) { return gi->compose(v); };
  } else {
    refuse_options(a.given, std::array{"--part"}, "an image basis (its images are whole)");
    try {
      previews.emplace(render::ImageBasis::open(*a.basis));
    } catch (const Error& e) {
      throw Error(*a.basis + ": not a matlas basis (an image basis from matlas basis, or a GI basis from matlas basis "
                             "--scene floor): " + e.what());
    }
    const auto fp = previews->metadata().find("model_fingerprint");
    if (previews->count() != model.count() || fp == previews->metadata().end() ||
        fp->second != atlas::model_fingerprint(model))
      throw Error(*a.basis + ": the basis was rendered for another model than " + a.input);
    compose = key = [&](const Eigen::VectorXd& v) { return previews->compose(v); };
  }
  const auto start = std::chrono::steady_clock::now();
  Image image = compose(w);
  const double ms = 1e3 * seconds_since(start);
  if (a.remove_fireflies) print(io.out, "removed %d fireflies\n", render::remove_fireflies(image));
  if (a.auto_exposure) tone.exposure += render::auto_exposure(key(Eigen::VectorXd::Zero(model.count())));
  write_image(a.output, image, tone);
  print(io.out, "composed %dx%d from %d materials in %.1f ms; wrote %s\n", image.width, image.height, model.count(),
        ms, a.output.c_str());
}

void run_render(const RenderArgs& a, const Io& io) {
  if (a.integrator != "direct" && a.integrator != "path") throw Error("--integrator must be direct or path");
  if (a.part != "all" && a.part != "i1" && a.part != "i2" && a.part != "p") throw Error("--part must be all, i1, i2 or p");
  if (a.basis) return compose_basis(a, io);
  if (a.auto_exposure) throw Error("--auto-exposure applies to --basis");
  if (a.remove_fireflies) throw Error("--remove-fireflies applies to --basis");
  const ToneMap tone = a.options.tone();
  TerminalProgress progress;
  render::RenderStats stats;
  std::optional<render::RefinementState> refined;
  const Image image = pathtrace::is_scene(a.options.scene) ? render_gi_scene(a, progress, stats)
                                                           : render_preview_scene(a, progress, stats, refined);
  write_image(a.output, image, tone);
  if (refined)
    print(io.out, "wrote %s (%dx%d, %d spp, estimated error %.2f %%%s, %.2f s)\n", a.output.c_str(), image.width,
          image.height, refined->spp, 100 * refined->relative_error,
          refined->relative_error <= *a.target_error ? "" : ": --spp reached before the target", stats.seconds);
  else
    print(io.out, "wrote %s (%dx%d, %d spp, %.2f s, %.3g camera samples/s)\n", a.output.c_str(), image.width,
          image.height, a.options.spp, stats.seconds,
          static_cast<double>(stats.camera_samples) / std::max(stats.seconds, 1e-9));
}

/// The command under a name: `render`, or a former name with its former defaults.
struct Variant {
  const char* name;
  const char* description;
  std::string scene = "sphere";
  int width = 512, height = 512;
  bool basis_required = false;
};

void add_variant(CLI::App& app, const Io& io, const Variant& v) {
  auto* cmd = app.add_subcommand(v.name, v.description);
  if (std::string(v.name) != "render") cmd->group("");  // a former name: not listed
  auto a = std::make_shared<RenderArgs>();
  a->options.scene = v.scene;
  a->options.width = v.width;
  a->options.height = v.height;
  cmd->add_option("input", a->input,
                  "MERL .binary file, .matlas model, or a fit report (.json from matlas fit: its analytic model itself)")
      ->required();
  cmd->add_option("-o,--output", a->output, "Output image: .png (tone mapped sRGB) or .exr (linear)")->required();
  add_point_options(*cmd, a->at, a->material);
  add_render_options(*cmd, a->options);
  cmd->add_option("--target-error", a->target_error,
                  "The previews' scene, direct lighting: refine until the estimated relative RMS error inside the object "
                  "is at most this (e.g. 0.01), with adaptive sampling; --spp is then the most samples per pixel "
                  "(default 4096)");
  cmd->get_option("--scene")
      ->description("The previews' scene, its object: sphere, bunny, suzi or a .glb/.gltf/.obj file; or a GI scene: "
                    "floor, box, NAME@VIEW (side, above) or a .json file (path-traced)");
  cmd->add_option("--integrator", a->integrator,
                  "The previews' scene: direct (their direct lighting) or path (the path tracer over the same scene: "
                  "light bouncing between the object and the ground). GI scenes are path-traced")
      ->capture_default_str();
  add_path_options(*cmd, a->path);
  cmd->add_option("--part", a->part,
                  "Path-traced image: all, i1 (paths touching the object at most once), i2 or p (never touching it); "
                  "GI basis: all or i1")
      ->capture_default_str();
  auto* basis = cmd->add_option("--basis", a->basis,
                                "Compose this basis at the point instead of rendering: an image basis (matlas basis) or "
                                "a GI basis (matlas basis --scene floor)");
  if (v.basis_required) basis->required();
  cmd->add_flag("--auto-exposure", a->auto_exposure,
                "With --basis: add the scene's automatic exposure (its log-average luminance with the mean material to "
                "middle grey), as the browser's scene view does by default");
  cmd->add_flag("--remove-fireflies", a->remove_fireflies,
                "With --basis: replace lone pixels and lone pairs over 2.5x their other neighbours by their neighbours' median, as "
                "the browser's scene view does while dragging (biased: the composition is then no longer linear)");
  cmd->callback([io, a, cmd, name = std::string(v.name)] {
    a->given = given_options(*cmd);
    if (name != "render")
      io.err << "matlas " << name << " is deprecated: use matlas render (--scene floor for a GI scene, --basis B for a "
             << "basis)\n";
    run_render(*a, io);
  });
}

void add_render_commands(CLI::App& app, const Io& io) {
  add_variant(app, io, {"render", "Render a material (.binary file, model point or fit report): the previews' scene by direct "
                                  "lighting or path tracing, a GI scene (floor, box, .json) path-traced, or a basis composed"});
  // Former names, with their former defaults (not listed in --help).
  add_variant(app, io, {"gi-render", "", "floor", 256, 256});
  add_variant(app, io, {"gi", "", "sphere", 512, 512, true});
}

}  // namespace

MATLAS_COMMAND(60, add_render_commands);

}  // namespace matlas::cli
