#pragma once
// Internal to src/gp: the optimiser implementations behind optimize_latent. Each runs until a stop
// rule fires and returns the reason in words; the best point is in the OptimizationRun.
#include <string>

#include "gp/optimize_run.h"

namespace matlas::gp::detail {

std::string run_lbfgs(OptimizationRun& run);
std::string run_hooke_jeeves(OptimizationRun& run);

}  // namespace matlas::gp::detail
