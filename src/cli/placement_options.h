#pragma once
// The sparse latent placement's options (--sparse-inducing, --sparse-rank, --sparse-block,
// --sparse-coarse), the same for `matlas build` and for `matlas evaluate`'s fits.
#include <CLI/CLI.hpp>

#include "gp/sparse_optimize.h"

namespace matlas::cli {

/// Adds the options to `cmd`, bound to `sparse` (defaults shown from its current values).
void add_sparse_placement_options(CLI::App& cmd, gp::SparseOptions& sparse);

}  // namespace matlas::cli
