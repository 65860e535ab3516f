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
  if (sparse.enabled() || materials < 1000 || !(placement_seconds > pass_seconds)) return {};
  char text[768];
  std::snprintf(text, sizeof text,
                "note: the exact latent placement of %zu materials took %.0f s against %.0f s for the data "
                "(O(n^3) per evaluation). --max-iterations 150 --coarse 300 (300 of them placed first, "
                "then a short refinement of all) takes a fraction of that, keeping the neighbourhoods "
                "but reconstructing the inputs less well; --sparse-inducing 100 costs O(n M^2) per "
                "evaluation, for several thousand materials (docs/BENCHMARKS.md, \"n = 1000 on one "
                "machine\", measures them)\n",
                materials, placement_seconds, pass_seconds);
  return text;
}

}  // namespace matlas::cli
