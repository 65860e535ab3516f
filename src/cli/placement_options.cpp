#include "cli/placement_options.h"

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

}  // namespace matlas::cli
