#pragma once
// The sparse latent placement's options (--sparse-inducing, --sparse-rank, --sparse-block,
// --sparse-coarse), the same for `matlas build` and for `matlas evaluate`'s fits.
#include <cstddef>
#include <string>

#include <CLI/CLI.hpp>

#include "gp/optimize.h"
#include "gp/sparse_optimize.h"

namespace matlas::cli {

/// Adds the options to `cmd`, bound to `sparse` (defaults shown from its current values).
void add_sparse_placement_options(CLI::App& cmd, gp::SparseOptions& sparse);

/// What `matlas build` tells a user whose exact placement of `materials` took longer than the
/// pass over the data (from 1000 materials on): how to place them sooner and at what cost
/// (docs/BENCHMARKS.md, "n = 1000 on one machine"). Empty when there is nothing to say: sparse
/// already, fewer materials, or a placement no longer than the pass.
std::string placement_hint(std::size_t materials, const gp::SparseOptions& sparse, double pass_seconds,
                           double placement_seconds);

/// What `matlas build` says of a placement that did not converge ("" when it did): a note when the
/// automatic iteration limit (max_iterations -1 from gp::OptimizeOptions::kLargePlacement
/// materials on) ended it, where a short refinement is the choice, else a warning.
std::string convergence_message(std::size_t materials, int max_iterations, const gp::OptimizeResult& result);

}  // namespace matlas::cli
