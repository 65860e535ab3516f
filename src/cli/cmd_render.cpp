// matlas render: one picture of a material (a MERL .binary file, or a model point), by the
// previews' direct lighting or, over the same scene, by the path tracer.
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "atlas/gi_density.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/latent_point.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/merl_file.h"
#include "manifold/model.h"
#include "pathtrace/preview_scene.h"
#include "pathtrace/tracer.h"
#include "render/material.h"
#include "render/render.h"

namespace matlas::cli {

namespace {

struct RenderArgs {
  std::string input, output, integrator = "direct";
  std::optional<std::string> at, material;
  std::optional<int> max_depth;
  RenderOptions options;
};

bool is_merl(const std::string& path) {
  return path.size() > 7 && path.compare(path.size() - 7, 7, ".binary") == 0;
}

/// The path tracer over the preview's scene (pathtrace/preview_scene.h): the same picture with
/// global illumination, or its direct lighting alone with --max-depth 1.
Image trace_preview(const RenderArgs& a, const pathtrace::World& world, const render::Material& material,
                    pathtrace::FixedDensity density, ProgressSink& progress, render::RenderStats& stats) {
  pathtrace::TraceSettings t;
  t.width = a.options.width;
  t.height = a.options.height;
  t.spp = a.options.spp;
  t.seed = a.options.seed;
  if (a.max_depth) t.max_depth = *a.max_depth;
  t.density = std::move(density);
  const render::MaterialList bank({&material});
  const auto start = std::chrono::steady_clock::now();
  Image image = pathtrace::trace(world, &bank, t, progress).full(0);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats.camera_samples = static_cast<std::uint64_t>(t.width) * static_cast<std::uint64_t>(t.height) *
                         static_cast<std::uint64_t>(t.spp);
  return image;
}

void run_render(const RenderArgs& a, const Io& io) {
  if (a.integrator != "direct" && a.integrator != "path") throw Error("--integrator must be direct or path");
  const bool path = a.integrator == "path";
  if (a.max_depth && !path) throw Error("--max-depth applies to --integrator path");
  refuse_output_among_inputs(a.output, a.options.input_files({a.input}));
  const render::RenderSettings settings = a.options.settings();
  const ToneMap tone = a.options.tone();
  // One scene, two integrators: the preview's, or its GI scene for the path tracer.
  std::optional<render::Scene> scene;
  std::optional<pathtrace::World> world;
  if (path) world.emplace(pathtrace::preview_scene(a.options.scene_description()));
  else scene.emplace(a.options.scene_description());
  TerminalProgress progress;
  render::RenderStats stats;
  Image image;
  if (is_merl(a.input)) {
    if (a.at || a.material) throw Error("--at/--material apply to models, not to the MERL file " + a.input);
    const BrdfTable table = read_merl(a.input);
    const render::TableMaterial material(table);
    image = path ? trace_preview(a, *world, material, pathtrace::default_fixed_density(), progress, stats)
                 : render::render(*scene, material, settings, progress, &stats);
  } else {
    const Model model = Model::open(a.input);
    const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
    const Eigen::VectorXd w = a.material ? model.material_weights(model.index_of(*a.material)) : model.weights(x);
    // The model's fitted mixture (previews: the same samples as its bases; GI: its gi-render
    // density). The table of m(w) is built once: a render's millions of lookups then read one
    // value per channel, not a dot product of n.
    const atlas::ModelTableMaterial material(model, w);
    image = path ? trace_preview(a, *world, material, atlas::fit_gi_density(model), progress, stats)
                 : render::render(*scene, material, atlas::model_render_settings(model, settings), progress, &stats);
  }
  write_image(a.output, image, tone);
  print(io.out, "wrote %s (%dx%d, %d spp, %.2f s, %.3g camera samples/s)\n", a.output.c_str(), settings.width,
              settings.height, settings.spp, stats.seconds,
              static_cast<double>(stats.camera_samples) / std::max(stats.seconds, 1e-9));
}

void add_render_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("render", "Render a material (.binary file or model point) to .png or .exr");
  auto a = std::make_shared<RenderArgs>();
  cmd->add_option("input", a->input, "MERL .binary file or .matlas model")->required();
  cmd->add_option("-o,--output", a->output, "Output image: .png (tone mapped sRGB) or .exr (linear)")->required();
  cmd->add_option("--at", a->at, "Latent point x1,...,xq (models)");
  cmd->add_option("--material", a->material, "Database material by name (models)");
  add_render_options(*cmd, a->options);
  cmd->add_option("--integrator", a->integrator,
                  "direct (the previews' direct lighting) or path (the path tracer over the same scene: light "
                  "bouncing between the object and the ground; --sampler and --grazing-samples do not apply)")
      ->capture_default_str();
  cmd->add_option("--max-depth", a->max_depth, "Scattering vertices per path (--integrator path; 8 by default, 1: direct "
                                               "lighting only)")
      ->check(CLI::Range(1, 64));
  cmd->callback([io, a] { run_render(*a, io); });
}

}  // namespace

MATLAS_COMMAND(60, add_render_command);

}  // namespace matlas::cli
