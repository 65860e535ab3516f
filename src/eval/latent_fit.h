#pragma once
// Latent placement and projection for the evaluation, on Gram matrices only: fitting the GP-LVM
// to (a subset of) the materials and projecting a left-out material onto the fitted map.
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "gp/convex_weights.h"
#include "gp/optimize.h"
#include "gp/posterior.h"
#include "manifold/build.h"

namespace matlas::eval {

struct FitOptions {
  double nugget = 1e-4;           ///< as BuildOptions::nugget
  /// As BuildOptions::optimize: starts 0 (the default) means BuildOptions::default_starts(q).
  gp::OptimizeOptions optimize = BuildOptions::default_optimize();
  gp::LatentPrior prior = gp::LatentPrior::spread();  ///< as BuildOptions::prior
  /// Convex interpolation (BuildOptions::interpolation == convex) with this ridge; 0 = GP weights.
  double convex_ridge = 1e-2;
  /// As BuildOptions::sparse: the sparse placement (inducing points) when enabled, for studies of
  /// databases whose exact fits cost O(n^3) per likelihood evaluation.
  gp::SparseOptions sparse{};
};

/// Latent points fitted to a centred Gram (of the layout transform), as a build places them: PCA
/// initialisation, then maximisation of the GP log-likelihood (place_latent_points, exact or
/// sparse).
struct LatentFit {
  std::shared_ptr<const gp::GpPosterior> posterior;
  /// The convex mode's projection (metric: the fitted Gram), or null for GP weights.
  std::shared_ptr<const gp::ConvexProjection> convex;
  /// The interpolation weights of x in the fit's mode (over the fitted materials).
  Eigen::VectorXd weights(const Eigen::VectorXd& x) const {
    return convex ? convex->from_centred(posterior->weights(x)) : posterior->weights(x);
  }
  /// The same along a sequence of nearby points (an optimiser's): each convex solve starts from
  /// the previous one's (gp::ConvexProjection::WarmStart).
  Eigen::VectorXd weights(const Eigen::VectorXd& x, gp::ConvexProjection::WarmStart& warm) const {
    return convex ? convex->from_centred(posterior->weights(x), warm) : posterior->weights(x);
  }
  double log_likelihood = 0;
  const Eigen::MatrixXd& latent() const { return posterior->latent(); }
};

/// Fits q-dimensional latent points to the centred Gram (columns = D', the number of data
/// columns). Throws matlas::Error as the GP code does.
LatentFit fit_latent(const Eigen::MatrixXd& centred_gram, double columns, int q,
                     const FitOptions& options);

/// The projection of a material onto a fitted map: manifold/project.h's concept (the latent point
/// whose reconstruction is nearest the material, searched from the latent points of the nearest
/// materials, manifold's nearest_materials), measured in a Gram matrix instead of a model file.
struct GramProjection {
  Eigen::VectorXd x;             ///< latent point
  Eigen::VectorXd coefficients;  ///< raw coefficients (length n) of m(x) over all n materials
  double residual_squared = 0;   ///< ||z_h - m(x)||^2 in the Gram's space
  /// Candidate reconstructions (raw coefficients) for a final choice by a metric the Gram cannot
  /// express (the cube-root distance, not quadratic): for each start, the points from the start
  /// (a material's own latent point) to its optimum, at t = 0, 1/4, 1/2, 3/4, 1.
  std::vector<Eigen::VectorXd> candidates;
};

/// Projects material h onto a map fitted to `subset` (the rows of the fit, in order): minimises
/// the residual ||z_h - m(x)||^2 measured in `gram` (a Gram of all n materials, the space the
/// objective is measured in) over x, by Nelder-Mead started from the latent points of the
/// `starts` subset materials closest to h in that Gram. Deterministic.
GramProjection project_in_gram(const LatentFit& fit, std::span<const int> subset,
                               const Eigen::MatrixXd& gram, int h, int starts = 3);

}  // namespace matlas::eval
