#pragma once
// How usable a built map is (docs/EVALUATION.md, item 8):
//   - layout readability: the share of materials whose nearest latent neighbour is closer than 1 %
//     of the layout's extent (the diagonal of the latent points' bounding box), and the
//     trustworthiness (Venna & Kaski 2001) of the k = 5 latent neighbourhoods against the
//     cube-root perceptual distance between the inputs;
//   - plausibility per interpolation mode, exact over every kept value: at the midpoints of
//     nearest-neighbour pairs, and at random points of the convex hull of the latent points
//     (convex combinations of three latent points): the share of points whose table has a negative
//     value, the largest share of negative values, and the largest directional albedo over the
//     inputs' largest.
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "manifold/model.h"

namespace matlas::eval {

struct LayoutReadability {
  double extent = 0;              ///< diagonal of the latent bounding box
  double crowded_share = 0;       ///< nearest neighbour closer than 1 % of the extent
  int crowded = 0;
  /// Of the `neighbours` nearest latent neighbours, against the cube-root distance; NaN where it is
  /// undefined (fewer than 4 materials).
  double trustworthiness = std::numeric_limits<double>::quiet_NaN();
  int neighbours = 5;             ///< k: 5, or (n - 2) / 2 for fewer than 12 materials
};

struct ModePlausibility {
  std::string mode;               ///< "gp" or "convex"
  std::string where;              ///< "midpoints" or "hull"
  int points = 0;
  int with_negative = 0;          ///< points whose table has at least one negative value (of those counted)
  int value_stride = 1;           ///< every s-th value counted (1: all; ManifoldQualityOptions::negative_budget)
  double mean_negative_share = 0; ///< mean over points of the share of negative values
  double worst_negative_share = 0;
  double worst_albedo_ratio = 0;  ///< largest albedo over the inputs' largest albedo (<= 1: no gain)
  double most_negative_weight = 0;  ///< smallest interpolation weight seen
};

struct ManifoldQuality {
  LayoutReadability layout;
  std::vector<ModePlausibility> plausibility;  ///< per mode and place
  double inputs_max_albedo = 0;
  int input_negative_values = 0;  ///< negative values among the inputs themselves (kept columns)
};

struct ManifoldQualityOptions {
  int hull_points = 400;  ///< random points in the convex hull of the latent points
  /// Midpoints of at most this many materials' nearest-neighbour pairs, the materials spread
  /// evenly over the list (0: every material).
  int midpoints = 200;
  int value_stride = 7;   ///< every s-th value for the perceptual distances of the trustworthiness
  /// Multiply-adds one negative-value count of a set of points may take (points x n x values);
  /// beyond it the count looks at every s-th value (ModePlausibility::value_stride). 100
  /// materials count every value; 1000 every 6th.
  double negative_budget = 5e11;
  unsigned seed = 1;
};

/// Trustworthiness of the k-neighbourhoods of the low-dimensional points (n x q) against the
/// squared high-dimensional distances (n x n): 1 when every latent neighbour is a true neighbour.
double trustworthiness(const Eigen::MatrixXd& high_squared_distances, const Eigen::MatrixXd& latent, int k);

/// The share of points whose nearest neighbour is closer than `fraction` of the bounding-box
/// diagonal, with the diagonal.
LayoutReadability layout_readability(const Eigen::MatrixXd& latent, double fraction = 0.01);

/// All of the above for a model, in both interpolation modes (each query names its mode).
ManifoldQuality assess_manifold(const Model& model, const ManifoldQualityOptions& options = {},
                                ProgressSink& progress = null_progress());

}  // namespace matlas::eval
