#pragma once
// The rotated-ZH coefficients of a model (issue 12): every input material as the model
// reconstructs it (its table at weights e_i) and the model's mean table, so that a map point with
// weights w has the coefficients mean + sum_i w_i (lambda_i - mean), the tables' own combination
// (zonal/coefficients.h, docs/REALTIME.md). Used by `matlas zonal MODEL` and the server's
// real-time viewer endpoints.
#include "manifold/model.h"
#include "zonal/coefficient_file.h"

namespace matlas::atlas {

/// Projects the n materials and the mean of `model` with `settings` (names from the model).
zonal::CoefficientSet model_coefficients(const Model& model, const zonal::ProjectionSettings& settings);

}  // namespace matlas::atlas
