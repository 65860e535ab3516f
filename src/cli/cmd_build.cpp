// matlas build DIR|FILES... -o MODEL.matlas --dim q: build a material manifold.
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/placement_options.h"
#include "cli/print.h"
#include "cli/latent_point.h"
#include "cli/world.h"
#include "core/blas.h"
#include "core/error.h"
#include "core/progress.h"
#include "gp/likelihood.h"
#include "gp/optimize.h"
#include "manifold/build.h"

namespace matlas::cli {

namespace {

/// Up to this many inputs, the build names each file; beyond, it counts them per folder.
constexpr std::size_t kListedFiles = 24;

/// The flags' values; their defaults are the library's (BuildOptions), which Python's build uses too.
struct BuildArgs {
  inline static const BuildOptions kDefaults{};
  std::vector<std::string> inputs;
  std::string output;
  int dim = kDefaults.dim;
  double nugget = kDefaults.nugget;
  std::string optimizer = gp::to_string(kDefaults.optimize.method);
  std::string layout = kDefaults.layout.to_string();  // docs/EVALUATION.md
  std::string storage = "f32";
  int max_iterations = kDefaults.optimize.max_iterations;
  gp::LatentPrior prior = kDefaults.prior;
  int starts = 0;  ///< 0: BuildOptions::default_starts (3 for q <= 2, where the likelihood is multimodal, else 1)
  int coarse = kDefaults.optimize.coarse;
  double tolerance = kDefaults.optimize.tolerance;
  std::size_t block_columns = kDefaults.block_columns;
  std::string interpolation = to_string(kDefaults.interpolation);
  double convex_ridge = kDefaults.convex_ridge;
  gp::SparseOptions sparse = kDefaults.sparse;
  std::string preset;
  bool quiet = false;
};

/// `--preset paper`: the settings of Soler et al. 2018 (l = 1, fixed nugget 1e-4, Hooke-Jeeves on
/// the plain likelihood of the linear data, GP interpolation), so that its claims can be checked.
void apply_preset(BuildArgs& a, const CLI::App& cmd) {
  if (a.preset.empty()) return;
  if (a.preset != "paper") throw Error("--preset must be 'paper', got '" + a.preset + "'");
  auto unless_given = [&](const char* flag, auto& field, auto value) {
    if (cmd.count(flag) == 0) field = value;
  };
  const BuildOptions paper = BuildOptions::paper_preset();
  unless_given("--nugget", a.nugget, paper.nugget);
  unless_given("--optimizer", a.optimizer, std::string(gp::to_string(paper.optimize.method)));
  unless_given("--layout", a.layout, paper.layout.to_string());
  unless_given("--interpolation", a.interpolation, std::string(to_string(paper.interpolation)));
  unless_given("--starts", a.starts, paper.optimize.starts);
  unless_given("--max-iterations", a.max_iterations, paper.optimize.max_iterations);
  unless_given("--coarse", a.coarse, paper.optimize.coarse);
  unless_given("--repulsion", a.prior.repulsion, paper.prior.repulsion);
  unless_given("--repulsion-radius", a.prior.radius, paper.prior.radius);
  unless_given("--latent-precision", a.prior.precision, paper.prior.precision);
}

void run_build(const BuildArgs& a, const Io& io) {
  // Under mpirun, every rank opens the set and reads its share of the files; rank 0 reports.
  Communicator& comm = world();
  const bool quiet = a.quiet || !comm.is_root();
  TerminalProgress progress(!quiet);
  std::vector<std::filesystem::path> inputs(a.inputs.begin(), a.inputs.end());
  std::optional<MaterialSet> opened;
  run_collectively(comm, [&] { opened.emplace(MaterialSet::open(inputs, progress)); });
  const MaterialSet& set = *opened;
  BuildOptions o;
  o.dim = a.dim;
  o.nugget = a.nugget;
  o.layout = LayoutTransform::parse(a.layout);
  o.optimize.method = gp::optimizer_from_string(a.optimizer);
  o.optimize.max_iterations = a.max_iterations;
  o.optimize.tolerance = a.tolerance;
  o.optimize.starts = a.starts;  // 0: BuildOptions::default_starts
  o.optimize.coarse = a.coarse;
  o.sparse = a.sparse;
  if (a.storage == "f16") o.storage = Storage::f16;
  else if (a.storage != "f32") throw Error("--storage must be f32 or f16, got '" + a.storage + "'");
  o.block_columns = a.block_columns;
  o.interpolation = interpolation_from_string(a.interpolation);
  o.convex_ridge = a.convex_ridge;
  o.prior = a.prior;

  if (!quiet) {
    print(io.err, "building a q=%d manifold of %zu materials (%s grid)", a.dim, set.size(),
          set.dims().to_string().c_str());
    if (comm.size() > 1) print(io.err, " on %d MPI ranks, each reading 1/%d of every file", comm.size(), comm.size());
    print(io.err, ":\n");
    if (set.size() <= kListedFiles) {
      for (std::size_t i = 0; i < set.size(); ++i)
        print(io.err, "  %s%s\n", set.file(i).path().string().c_str(),
                     set.resampled(i) ? "  (RGL, resampled onto the MERL grid)" : "");
    } else {  // a line per folder, not a thousand lines
      struct Count {
        std::size_t files = 0, resampled = 0;
      };
      std::map<std::string, Count> folders;
      for (std::size_t i = 0; i < set.size(); ++i) {
        Count& c = folders[set.file(i).path().parent_path().string()];
        ++c.files;
        c.resampled += set.resampled(i) ? 1 : 0;
      }
      for (const auto& [folder, c] : folders) {
        print(io.err, "  %zu files in %s", c.files, folder.c_str());
        if (c.resampled > 0) print(io.err, " (%zu RGL, resampled onto the MERL grid)", c.resampled);
        print(io.err, "\n");
      }
    }
    if (!set.ignored().empty()) {
      print(io.err, "ignored %zu file(s) that are neither .binary nor .bsdf:", set.ignored().size());
      for (const auto& p : set.ignored()) print(io.err, " %s", p.filename().string().c_str());
      print(io.err, "\n");
    }
  }
  const BuildReport r = build_model(set, o, a.output, progress, comm);
  if (!comm.is_root()) return;
  print(io.out, "wrote %s\n", a.output.c_str());
  if (comm.size() > 1)
    print(io.out, "  ranks            %d (MPI), the pass split by column blocks; rank 0: its share %.2f s, waiting "
                  "for the others %.2f s, Gram sums and gathers %.2f s, the ranks' data placed %.2f s\n",
          comm.size(), r.share_seconds, r.wait_seconds, r.reduce_seconds, r.place_seconds);
  print(io.out, "  materials        %zu, q = %d, layout %s, optimiser %s, interpolation %s\n", set.size(), a.dim,
              o.layout.to_string().c_str(), gp::to_string(o.optimize.method), to_string(o.interpolation));
  print(io.out, "  columns          %zu kept, %zu dropped (not measured in every material)\n",
              r.kept_columns, r.dropped_columns);
  print(io.out, "  log-likelihood   %.10g (%d iterations, %d evaluations; %s)\n", r.log_likelihood,
              r.optimization.iterations, r.optimization.evaluations, r.optimization.stop_reason.c_str());
  print(io.err, "%s", convergence_message(set.size(), a.max_iterations, r.optimization).c_str());
  if (const std::string hint = placement_hint(set.size(), o.sparse, r.pass_seconds, r.optimize_seconds); !hint.empty())
    print(io.err, "%s", hint.c_str());
  print(io.out, "  storage          %s, relative L2 rounding error %.3g\n",
              o.storage == Storage::f16 ? "float16" : "float32", r.storage_relative_error);
  print(io.out, "  time             reading %.2f s, latent placement %.2f s, finishing the file %.2f s\n",
              r.pass_seconds, r.optimize_seconds, r.finish_seconds);
  print(io.out, "  reading          centring and data %.2f s, Gram and albedo with the next files %.2f s, "
                "first files and masks %.2f s\n",
              r.pass_steps.sweep, r.pass_steps.products, r.pass_steps.read);
  // Which kernels the Gram matrices and the placement ran on (OPENBLAS_CORETYPE overrides).
  print(io.out, "  blas             %s\n", blas::description().c_str());
  if (const std::string note = blas::kernel_override_note(); !note.empty())
    print(io.out, "  blas note        %s\n", note.c_str());
}

void add_build_command(CLI::App& app, const Io& io) {
  auto args = std::make_shared<BuildArgs>();
  auto* cmd = app.add_subcommand("build", "Build a material manifold (.matlas model) from MERL .binary and RGL .bsdf files");
  cmd->add_option("inputs", args->inputs, "A folder of MERL .binary and/or RGL .bsdf files (other files are ignored) or a list of files; "
                  "isotropic .bsdf files are resampled onto the MERL grid")
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
  cmd->add_option("--max-iterations", args->max_iterations,
                  "Optimiser iteration limit (of the refinement of all after a coarse stage). -1, the "
                  "default: 5000, and from 500 materials on 10^11/n^3, at least 100 (an iteration costs "
                  "O(n^3); docs/GP.md)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--starts", args->starts,
                  "Optimiser starts (the PCA start and rescaled copies; the best wins). Default: 3 "
                  "for q <= 2, where the likelihood has several maxima, else 1")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--coarse", args->coarse,
                  "Coarse-to-fine exact placement: place C materials chosen at random first (themselves "
                  "coarse-to-fine from C/5 when that is 30 or more), the others from their nearest ones in the "
                  "data, then refine all. 0: all at once; -1, the default: 0.3 n from 500 materials on, else 0 "
                  "(docs/GP.md)")
      ->check(CLI::Range(-1, 100000000))
      ->capture_default_str();
  add_sparse_placement_options(*cmd, args->sparse);
  cmd->add_option("--tolerance", args->tolerance, "Optimiser relative tolerance")
      ->check(finite_number() & CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--block-columns", args->block_columns,
                  "Columns per streamed block, 64 or more; 0: by the number of materials (4096 up to 511, "
                  "16384 from 512 on, narrower where a block would pass 256 MB)")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            std::size_t v = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
            const bool ok = ec == std::errc{} && end == text.data() + text.size() &&
                            (v == 0 || (v >= 64 && v <= (std::size_t{1} << 24)));
            return ok ? "" : "must be 0 or a whole number from 64 to 16777216";
          },
          "0 or 64..16777216"))
      ->capture_default_str();
  cmd->add_option("--interpolation", args->interpolation,
                  "convex (default: non-negative weights summing to 1, every table a convex combination of "
                  "the inputs) or gp (the paper's GP weights, of any sign)")
      ->capture_default_str();
  cmd->add_option("--convex-ridge", args->convex_ridge,
                  "Relative ridge of the convex mode's projection metric (larger: closer to the Euclidean "
                  "projection of the weights)")
      ->capture_default_str();
  cmd->add_option("--repulsion", args->prior.repulsion,
                  "Weight of the repulsive prior between latent points (0: off, as in the paper)")
      ->capture_default_str();
  cmd->add_option("--repulsion-radius", args->prior.radius,
                  "Distance (lengthscale units) below which latent points repel each other")
      ->capture_default_str();
  cmd->add_option("--latent-precision", args->prior.precision,
                  "Precision of the Gaussian prior that bounds the layout's extent (0: off)")
      ->capture_default_str();
  cmd->add_option("--preset", args->preset,
                  "paper: Soler et al. 2018's settings (nugget 1e-4, Hooke-Jeeves, linear layout, no "
                  "priors, GP interpolation, one start); explicit flags still win");
  cmd->add_flag("--quiet", args->quiet, "No progress output");
  cmd->callback([io, args, cmd] {
    apply_preset(*args, *cmd);
    run_build(*args, io);
  });
}

}  // namespace

MATLAS_COMMAND(30, add_build_command);

}  // namespace matlas::cli
