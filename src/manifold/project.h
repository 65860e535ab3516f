#pragma once
// Projection of a new measured material onto a model's map: the latent point x whose BRDF m(x)
// is closest (L2 over the model's kept columns) to the material. This is the one home of the
// concept: the evaluation's leave-one-out (eval/latent_fit.h, project_in_gram) is the same
// search measured in a Gram matrix instead of a model file, from the same starts
// (nearest_materials).
//
// Two passes over the table: the first measures d_i = |z - z_i|^2 for every input and picks the
// nearest input j; the second computes g_i = <z - z_j, z_i - mean>. With u = w(x) - e_j the
// residual of any x is then |z - m(x)|^2 = d_j - 2 u^T g + u^T S u (S the model's centred Gram),
// anchored at the nearest input so that no large terms cancel; the search runs entirely in
// n-space: L-BFGS with the analytic gradient, started from the latent points of the nearest
// materials.
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "manifold/model.h"

namespace matlas {

/// What the pass over a material measures against a model.
struct MaterialInnerProducts {
  Eigen::VectorXd distance2;    ///< d_i = |z - z_i|^2 over the kept columns
  int anchor = 0;               ///< j, the nearest input
  Eigen::VectorXd g;            ///< g_i = <z - z_j, z_i - mean>
  double norm2 = 0;             ///< |z|^2 (for relative errors)
  std::size_t missing = 0;      ///< kept columns the material has no measurement for (skipped)
};

MaterialInnerProducts inner_products(const Model& model, const BrdfTable& table);

struct Projection {
  Eigen::VectorXd x;            ///< the latent point
  double residual2 = 0;         ///< |z - m(x)|^2 over the kept columns
  double relative_error = 0;    ///< sqrt(residual2 / |z|^2)
  double variance = 0;          ///< predictive variance at x
  int nearest = -1;             ///< nearest database material (in data space)
  double nearest_relative_error = 0;
  std::size_t missing = 0;      ///< see MaterialInnerProducts
};

/// The starts of a projection: indices of the `count` materials with the smallest squared
/// distances to the material (nearest first, ties in index order; fewer if there are fewer).
std::vector<int> nearest_materials(const Eigen::Ref<const Eigen::VectorXd>& distance2, int count);

/// Residual |z - m(x)|^2 and, if `gradient` is given, its gradient with respect to x. `warm`, if
/// given, starts the convex solves from the previous evaluation's (an optimiser's points are
/// near each other; the weights, hence the residual, are the same: Model::weights(x, warm)).
double projection_residual(const Model& model, const MaterialInnerProducts& ip, const Eigen::VectorXd& x,
                           Eigen::VectorXd* gradient = nullptr, Model::WarmStart* warm = nullptr);

/// Projects a material (same grid as the model) onto the model. `starts` nearest materials seed
/// the search, plus the centroid of the latent points.
Projection project_material(const Model& model, const BrdfTable& table, int starts = 5);

}  // namespace matlas
