#pragma once
// The results of the study's latent fits as arrays of doubles, and back: a study split across
// processes (run_layout_study with a Communicator) shares its fits out by job and exchanges these
// records, so every rank plans the same distances from the same bits.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "eval/latent_fit.h"

namespace matlas::eval {

/// A fit of all materials: its seconds, log-likelihood and latent points.
std::vector<double> fit_record(double seconds, double log_likelihood, const Eigen::MatrixXd& latent);
/// Reads fit_record's array; matlas::InternalError when it is not one.
void read_fit_record(std::span<const double> record, double& seconds, double& log_likelihood, Eigen::MatrixXd& latent);

/// A left-out material's projection: its seconds, residual, point, coefficients and candidates.
std::vector<double> projection_record(double seconds, const GramProjection& projection);
/// Reads projection_record's array; matlas::InternalError when it is not one.
void read_projection_record(std::span<const double> record, double& seconds, GramProjection& projection);

}  // namespace matlas::eval
