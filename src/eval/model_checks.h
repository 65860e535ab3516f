#pragma once
// Checks of a built model (docs/EVALUATION.md, items 1 to 4):
//   1. exact interpolation: m(x_i) against each input table (max and mean error);
//   2. reciprocity: exported tables give f(wi, wo) = f(wo, wi) on random direction pairs;
//   3. albedo linearity: the albedo of m(x) against the weighted sum of the inputs' albedos;
//   4. physical plausibility over the map: fraction of negative values (what the export clamps)
//      and the largest directional albedo on a dense grid over the region the data covers.
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "brdf/albedo.h"
#include "core/progress.h"
#include "manifold/material_set.h"
#include "manifold/model.h"

namespace matlas::eval {

struct ModelCheckOptions {
  int reciprocity_pairs = 2000;  ///< random direction pairs per sample point
  int sample_points = 8;         ///< latent points for reciprocity and albedo checks
  int map_resolution = 32;       ///< grid cells per axis for the plausibility map
  /// Item 1 checks at most this many materials, spread evenly over the list (0: all). Its cost
  /// is (checked materials) x n x values multiply-adds: all 1000 of a 1000-material model would
  /// be 4.4e12, half an hour here; 200 of them take about a minute.
  int interpolation_materials = kInterpolationMaterials;
  static constexpr int kInterpolationMaterials = 200;
  AlbedoQuadrature albedo_quadrature{};  ///< quadrature of the albedo check (the model's)
  unsigned seed = 1;
};

/// Item 1, per checked material (`materials`: their indices in the model, all of them or an even
/// spread, ModelCheckOptions::interpolation_materials).
struct InterpolationCheck {
  bool available = false;               ///< false when the source tables could not be read
  std::string note;
  std::vector<int> materials;           ///< the checked materials, in the order of the vectors below
  std::vector<double> max_abs_error;    ///< max |m(x_i) - z_i| over kept values (physical units)
  std::vector<double> mean_abs_error;
  std::vector<double> max_relative_error;  ///< max abs error / max |z_i|
  double max_weight_error = 0;          ///< max_i |w(x_i) - e_i|_inf
  /// Values kept by the model but missing in a checked source; with every material checked, also
  /// values every source measures that the model drops.
  std::size_t column_mismatches = 0;
};

/// Item 2.
struct ReciprocityCheck {
  int points = 0, pairs = 0;
  std::size_t unequal = 0;       ///< direction pairs with f(wi, wo) != f(wo, wi) in some channel
  double max_relative_difference = 0;
};

/// Item 3, per sample point and angle.
struct AlbedoCheck {
  std::vector<double> angles_degrees;      ///< theta_o of the compared albedos
  double max_relative_error = 0;           ///< m(x) with its signed values vs weighted sum of inputs
  double max_relative_error_clamped = 0;   ///< clamped export vs weighted sum (effect of the clamp)
  double max_relative_error_model = 0;     ///< model's albedo_curve vs weighted sum
  std::vector<std::vector<double>> rows;   ///< point, angle, channel, table, weighted sum, clamped
};

/// Item 4.
struct PlausibilityMap {
  int resolution = 0;
  int axis_x = 0, axis_y = 1;         ///< latent axes of the map (the others at the data mean)
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  std::vector<double> negative_fraction;  ///< row-major, resolution^2 (y major)
  std::vector<double> max_albedo;         ///< largest directional albedo over angles and channels
  std::vector<double> variance;           ///< GP predictive variance (where the data is)
  double worst_negative_fraction = 0, worst_max_albedo = 0;
  double data_max_albedo = 0;             ///< largest albedo among the inputs
  std::size_t values = 0;                 ///< kept values per table
  /// export_table at the worst grid point: values clamped to 0 (cross-check of the export path).
  std::size_t export_clamped_at_worst = 0;
};

struct ModelChecks {
  std::string model_path;
  int count = 0, dim = 0;
  std::string layout;
  Eigen::MatrixXd latent;  ///< the model's latent points (n x q)
  InterpolationCheck interpolation;
  ReciprocityCheck reciprocity;
  AlbedoCheck albedo;
  PlausibilityMap map;
};

/// Runs the four checks. `sources` (the input tables, in the model's order) are needed for item 1;
/// pass nullptr when they are not available.
ModelChecks run_model_checks(const Model& model, const MaterialSet* sources,
                             const ModelCheckOptions& options, ProgressSink& progress = null_progress());

/// Negative values per weight vector (columns of `weights`, n x m), counted over the model's kept
/// values by one pass over its storage: m x n x values multiply-adds. With `stride` > 1 only
/// every stride-th value of the table is looked at; `visited`, when given, receives the number of
/// kept values looked at (the denominator of a share).
std::vector<std::size_t> count_negative_values(const Model& model, const Eigen::MatrixXd& weights,
                                               std::size_t stride = 1, std::size_t* visited = nullptr);

/// The same for the inputs themselves (the columns of the identity), read from the stored values
/// in n x values steps instead of a product.
std::vector<std::size_t> count_negative_inputs(const Model& model);

/// Whether w is a convex combination (w >= 0, summing to 1 within 1e-9) of inputs without a
/// negative value (input_negatives: count_negative_inputs): then its table has none either, with
/// no product to count them.
bool non_negative_by_construction(const Eigen::Ref<const Eigen::VectorXd>& w,
                                  const std::vector<std::size_t>& input_negatives);

/// count_negative_values where a negative value can be: 0 without a product for the columns that
/// are non_negative_by_construction, the others counted on every `stride`-th value, the stride
/// the least that keeps their count within `budget` multiply-adds (columns x n x values).
struct NegativeCounts {
  std::vector<std::size_t> negatives;  ///< per column of the weights
  std::size_t stride = 1;
  std::size_t visited = 0;  ///< kept values looked at per counted column (all kept ones if none)
};
NegativeCounts count_possible_negatives(const Model& model, const Eigen::MatrixXd& weights,
                                        const std::vector<std::size_t>& input_negatives,
                                        double budget = std::numeric_limits<double>::infinity());

}  // namespace matlas::eval
