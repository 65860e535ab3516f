// matlas build DIR|FILES... -o MODEL.matlas --dim q: build a material manifold.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/latent_point.h"
#include "core/error.h"
#include "core/progress.h"
#include "manifold/build.h"

namespace matlas::cli {

namespace {

struct BuildArgs {
  std::vector<std::string> inputs;
  std::string output;
  int dim = 2;
  double nugget = 1e-4;
  std::string optimizer = "lbfgs";
  std::string layout = "cosine-linear";  // best in docs/EVALUATION.md
  std::string storage = "f32";
  int max_iterations = 1000;
  int starts = 0;  ///< 0: 3 for q <= 2 (the likelihood is multimodal there), else 1
  double tolerance = 1e-7;
  std::size_t block_columns = 4096;
  bool quiet = false;
};

void run_build(const BuildArgs& a) {
  TerminalProgress progress(!a.quiet);
  std::vector<std::filesystem::path> inputs(a.inputs.begin(), a.inputs.end());
  const MaterialSet set = MaterialSet::open(inputs);
  BuildOptions o;
  o.dim = a.dim;
  o.nugget = a.nugget;
  o.layout = LayoutTransform::parse(a.layout);
  o.optimize.method = gp::optimizer_from_string(a.optimizer);
  o.optimize.max_iterations = a.max_iterations;
  o.optimize.tolerance = a.tolerance;
  o.optimize.starts = a.starts > 0 ? a.starts : (a.dim <= 2 ? 3 : 1);
  if (a.storage == "f16") o.storage = Storage::f16;
  else if (a.storage != "f32") throw Error("--storage must be f32 or f16, got '" + a.storage + "'");
  o.block_columns = a.block_columns;

  if (!a.quiet) {
    std::fprintf(stderr, "building a q=%d manifold of %zu materials (%s grid):\n", a.dim, set.size(),
                 set.dims().to_string().c_str());
    for (std::size_t i = 0; i < set.size(); ++i)
      std::fprintf(stderr, "  %s\n", set.file(i).path().string().c_str());
    if (!set.ignored().empty()) {
      std::fprintf(stderr, "ignored %zu file(s) that are not .binary:", set.ignored().size());
      for (const auto& p : set.ignored()) std::fprintf(stderr, " %s", p.filename().string().c_str());
      std::fprintf(stderr, "\n");
    }
  }
  const BuildReport r = build_model(set, o, a.output, progress);
  std::printf("wrote %s\n", a.output.c_str());
  std::printf("  materials        %zu, q = %d, layout %s, optimiser %s\n", set.size(), a.dim,
              o.layout.to_string().c_str(), gp::to_string(o.optimize.method));
  std::printf("  columns          %zu kept, %zu dropped (not measured in every material)\n",
              r.kept_columns, r.dropped_columns);
  std::printf("  log-likelihood   %.10g (%d iterations, %d evaluations; %s)\n", r.log_likelihood,
              r.optimization.iterations, r.optimization.evaluations, r.optimization.stop_reason.c_str());
  std::printf("  storage          %s, relative L2 rounding error %.3g\n",
              o.storage == Storage::f16 ? "float16" : "float32", r.storage_relative_error);
  std::printf("  time             reading %.2f s, latent placement %.2f s, finishing the file %.2f s\n",
              r.pass_seconds, r.optimize_seconds, r.finish_seconds);
  std::printf("  reading          files %.2f s, centring and data %.2f s, Gram and albedo %.2f s\n",
              r.pass_steps.read, r.pass_steps.sweep, r.pass_steps.products);
}

void add_build_command(CLI::App& app) {
  auto args = std::make_shared<BuildArgs>();
  auto* cmd = app.add_subcommand("build", "Build a material manifold (.matlas model) from MERL .binary files");
  cmd->add_option("inputs", args->inputs, "A folder of MERL .binary files (other files are ignored) or a list of files")
      ->required();
  cmd->add_option("-o,--output", args->output, "Output model file (.matlas)")->required();
  cmd->add_option("-q,--dim", args->dim, "Latent dimension q (1..10)")->check(CLI::Range(1, 10))->capture_default_str();
  cmd->add_option("--nugget", args->nugget, "Nugget delta added to the diagonal of K")
      ->check(finite_number())
      ->capture_default_str();
  cmd->add_option("--optimizer", args->optimizer, "lbfgs (default) or hooke-jeeves (the paper's pattern search)")
      ->capture_default_str();
  cmd->add_option("--layout", args->layout,
                  "Data transform used to place the latent points: linear, cbrt or log, optionally "
                  "prefixed cosine- (the interpolation stays linear in the data)")
      ->capture_default_str();
  cmd->add_option("--storage", args->storage, "Precision of the stored data: f32 or f16")->capture_default_str();
  cmd->add_option("--max-iterations", args->max_iterations, "Optimiser iteration limit")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--starts", args->starts,
                  "Optimiser starts (the PCA start and rescaled copies; the best wins). Default: 3 "
                  "for q <= 2, where the likelihood has several maxima, else 1")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--tolerance", args->tolerance, "Optimiser relative tolerance")
      ->check(finite_number() & CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--block-columns", args->block_columns, "Columns per streamed block")
      ->check(CLI::Range(std::size_t{64}, std::size_t{1} << 24))
      ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No progress output");
  cmd->callback([args] { run_build(*args); });
}

}  // namespace

MATLAS_COMMAND(30, add_build_command);

}  // namespace matlas::cli
