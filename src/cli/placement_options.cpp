#include "cli/placement_options.h"

#include <cstdio>

namespace matlas::cli {

void add_sparse_placement_options(CLI::App& cmd, gp::SparseOptions& sparse) {
  cmd.add_option("--sparse-inducing", sparse.inducing,
                 "Sparse latent optimisation with M inducing points (0: exact). For thousands of "
                 "materials: O(n M^2) per evaluation instead of O(n^3) (docs/GP.md)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd.add_option("--sparse-rank", sparse.rank,
                 "Rank of the data term of the sparse optimisation (the rest of the trace spread evenly)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd.add_option("--sparse-block", sparse.block,
                 "Largest block of exact local covariance in the sparse optimisation (1: FITC)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd.add_option("--sparse-coarse", sparse.coarse,
                 "Coarse-to-fine sparse optimisation: place C materials chosen at random first, the others "
                 "from their nearest ones in the data, then refine all (0: all at once; -1, the default: n/10 "
                 "from 2000 materials on, else 0; docs/GP.md)")
      ->check(CLI::Range(-1, 100000000))
      ->capture_default_str();
}

std::string placement_hint(std::size_t materials, const gp::SparseOptions& sparse, double pass_seconds,
                           double placement_seconds) {
  if (sparse.enabled() || materials < static_cast<std::size_t>(gp::OptimizeOptions::kLargePlacement) ||
      !(placement_seconds > pass_seconds))
    return {};
  char text[768];
  std::snprintf(text, sizeof text,
                "note: the exact latent placement of %zu materials took %.0f s against %.0f s for the data "
                "(O(n^3) per evaluation). The automatic --max-iterations and --coarse (leave them out) keep "
                "it to a fraction of that from 500 materials on: 0.3 n of them placed first, then a short "
                "refinement of all; --sparse-inducing 100 costs O(n M^2) per evaluation, for several "
                "thousand materials (docs/BENCHMARKS.md, \"n = 1000 on one machine\", measures them)\n",
                materials, placement_seconds, pass_seconds);
  return text;
}

std::string convergence_message(std::size_t materials, int max_iterations, const gp::OptimizeResult& result) {
  if (result.converged()) return {};
  const auto n = static_cast<Eigen::Index>(materials);
  char text[768];
  if (max_iterations == -1 && n >= gp::OptimizeOptions::kLargePlacement && result.stop_reason == "iteration limit reached") {
    gp::OptimizeOptions automatic;
    automatic.max_iterations = -1;
    std::snprintf(text, sizeof text,
                  "note: the latent placement of %zu materials stopped at its automatic limit (a refinement of %d "
                  "iterations after the coarse-to-fine start, each O(n^3)); the layout is usable and would still "
                  "improve slowly: --max-iterations N for a longer refinement (docs/GP.md)\n",
                  materials, automatic.resolved(n).max_iterations);
  } else {
    std::snprintf(text, sizeof text,
                  "warning: the latent placement did not converge (%s); the model is usable but its layout is not a "
                  "maximum of the likelihood: raise --max-iterations or --starts\n",
                  result.stop_reason.c_str());
  }
  return text;
}

}  // namespace matlas::cli
