// matlas render: one picture of a material (a MERL .binary file, or a model point).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

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
#include "render/material.h"
#include "render/render.h"

namespace matlas::cli {

namespace {

struct RenderArgs {
  std::string input, output;
  std::optional<std::string> at, material;
  RenderOptions options;
};

bool is_merl(const std::string& path) {
  return path.size() > 7 && path.compare(path.size() - 7, 7, ".binary") == 0;
}

void run_render(const RenderArgs& a, const Io& io) {
  refuse_output_among_inputs(a.output, a.options.input_files({a.input}));
  const render::RenderSettings settings = a.options.settings();
  const ToneMap tone = a.options.tone();
  const render::Scene scene(a.options.scene_description());
  TerminalProgress progress;
  render::RenderStats stats;
  Image image;
  if (is_merl(a.input)) {
    if (a.at || a.material) throw Error("--at/--material apply to models, not to the MERL file " + a.input);
    const BrdfTable table = read_merl(a.input);
    image = render::render(scene, render::TableMaterial(table), settings, progress, &stats);
  } else {
    const Model model = Model::open(a.input);
    const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
    const Eigen::VectorXd w = a.material ? model.material_weights(model.index_of(*a.material)) : model.weights(x);
    // The model's fitted mixture: the same samples as its bases. The table of m(w) is built once:
    // a render's millions of lookups then read one value per channel, not a dot product of n.
    const atlas::ModelTableMaterial material(model, w);
    image = render::render(scene, material, atlas::model_render_settings(model, settings), progress, &stats);
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
  cmd->callback([io, a] { run_render(*a, io); });
}

}  // namespace

MATLAS_COMMAND(60, add_render_command);

}  // namespace matlas::cli
