// matlas basis: render the image basis of a model (instant previews of any latent point).
#include <cstdio>
#include <memory>
#include <string>

#include "atlas/model_basis.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "core/file_io.h"
#include "manifold/model.h"

namespace matlas::cli {

namespace {

struct BasisArgs {
  std::string model, output;
  std::string precision = "f16";
  std::string rank = "none";
  double tolerance = 1e-3;
  RenderOptions options;
};

void run_basis(BasisArgs a, const Io& io) {
  if (a.precision != "f16" && a.precision != "f32") throw Error("--precision must be f16 or f32");
  refuse_output_among_inputs(a.output, a.options.input_files({a.model}));
  const Model model = Model::open(a.model);
  const render::Scene scene(a.options.scene_description());
  TerminalProgress progress;
  render::ImageBasis basis = atlas::render_basis(model, scene, a.options.settings(), progress);
  print(io.out, "rendered %d material images (%dx%d, %d spp); object covers %.1f%% of the pixels\n", basis.count(),
              basis.width(), basis.height(), a.options.spp, 100.0 * basis.active_fraction());
  if (a.rank != "none") {
    int max_rank = 0;
    double tolerance = a.tolerance;
    if (a.rank == "full") tolerance = 0.0;
    else if (a.rank != "auto") {
      try {
        max_rank = std::stoi(a.rank);
      } catch (const std::exception&) {
        throw Error("--rank '" + a.rank + "': expected none, auto, full or a number");
      }
      if (max_rank <= 0) throw Error("--rank must be positive");
      tolerance = 0.0;
    }
    const render::LowRankReport r = basis.compress(tolerance, max_rank);
    print(io.out, "low-rank form: rank %d of %d, relative error %.3g (centred), %.3g (images), max abs %.3g\n", r.rank,
                basis.count(), r.relative_error, r.image_relative_error, r.max_abs_error);
  }
  if (a.precision == "f16") {
    render::ImageBasis copy = basis;
    print(io.out, "float16 storage: relative error %.3g\n", copy.convert_to_half());
  }
  basis.save(a.output, a.precision == "f16" ? render::BasisPrecision::f16 : render::BasisPrecision::f32);
  print(io.out, "wrote %s\n", a.output.c_str());
}

void add_basis_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("basis", "Render the image basis of a model (safetensors) for instant previews");
  auto a = std::make_shared<BasisArgs>();
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("-o,--output", a->output, "Output basis (.safetensors)")->required();
  cmd->add_option("--precision", a->precision, "Image storage: f16 or f32")->capture_default_str();
  cmd->add_option("--rank", a->rank, "Low-rank form: none, auto (--tolerance), full, or a rank")->capture_default_str();
  cmd->add_option("--tolerance", a->tolerance, "Relative error of the automatic rank")->capture_default_str();
  add_render_options(*cmd, a->options);
  cmd->callback([io, a] { run_basis(*a, io); });
}

}  // namespace

MATLAS_COMMAND(61, add_basis_command);

}  // namespace matlas::cli
