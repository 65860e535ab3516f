#pragma once
// The rotated-ZH coefficients of a model (issue 12): every input material as the model
// reconstructs it (its table at weights e_i) and the model's mean table, so that a map point with
// weights w has the coefficients mean + sum_i w_i (lambda_i - mean), the tables' own combination
// (zonal/coefficients.h, docs/REALTIME.md). Used by `matlas zonal MODEL` and the server's
// real-time viewer endpoints. `matlas zonal DB` projects a database's tables the same way.
//
// Split across processes (`mpirun -np P matlas zonal`, core/communicator.h): every rank projects a
// contiguous share of the tables (each table is projected on its own, so a share's coefficients
// are the single process's, to the order of the quadrature's sums) and rank 0 gathers them.
#include "core/communicator.h"
#include "core/progress.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "zonal/coefficient_file.h"

namespace matlas::atlas {

/// Projects the n materials and the mean of `model` with `settings` (names from the model). With
/// P > 1 ranks, the whole set on rank 0 and an empty one (names and settings only) elsewhere.
zonal::CoefficientSet model_coefficients(const Model& model, const zonal::ProjectionSettings& settings,
                                         Communicator& comm = serial_communicator());

/// Projects every table of a database (no mean), read file by file. Ranks as above; a file that
/// fails on one rank fails every rank with its message (run_collectively).
zonal::CoefficientSet database_coefficients(const MaterialSet& set, const zonal::ProjectionSettings& settings,
                                            Communicator& comm = serial_communicator(),
                                            ProgressSink& progress = null_progress());

}  // namespace matlas::atlas
