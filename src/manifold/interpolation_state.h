#pragma once
// What a client needs to compute Model::weights itself (GET /api/interpolation, docs/API.md), as
// plain matrices: the GP's latent points, kernel, nugget taper and Cholesky factor, and the convex
// mode's metric. The server serves it without knowing the GP's types.
#include <Eigen/Core>

namespace matlas {

class Model;

struct InterpolationState {
  Eigen::MatrixXd latent;          ///< n x q latent points
  double lengthscale = 0;          ///< the kernel's l
  double nugget = 0;               ///< the kernel's delta
  Eigen::VectorXd taper_radius;    ///< per point, the radius of the nugget's taper
  Eigen::MatrixXd cholesky_lower;  ///< L of K = L L^T
  Eigen::MatrixXd convex_metric;   ///< the convex mode's metric (Model::convex_metric)
};

InterpolationState interpolation_state(const Model& model);

}  // namespace matlas
