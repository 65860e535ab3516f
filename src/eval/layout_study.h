#pragma once
// The evaluation of latent maps on a database (docs/EVALUATION.md, items 5 to 7): for each
// layout transform and each latent dimension q,
//   - latent paths: pairs of materials, the straight latent segment between them sampled, the
//     perceptual distance between consecutive samples and between the ends, and how well latent
//     distance predicts perceptual distance (Spearman rank correlation);
//   - leave-one-out: each material left out, the map fitted without it, the material projected
//     onto it; its reconstruction error (cube-root and cosine-RMSE distances) against PCA with
//     mean + q components fitted without it and against the nearest remaining material.
// Everything is computed in Gram space (gram_space.h) except the perceptual distances, which come
// from one streaming pass over the tables for all combinations at once (combination_pass.h).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/communicator.h"
#include "core/progress.h"
#include "eval/brdf_distance.h"
#include "eval/latent_fit.h"
#include "manifold/gram.h"
#include "manifold/material_set.h"

namespace matlas::eval {

/// The value stride that keeps a pass over `tables` tables of `values_per_table` values within
/// `budget` compared values: ceil(tables x values / budget), at least 1.
int automatic_stride(std::size_t tables, std::size_t values_per_table, double budget);

/// How many materials the default study leaves out in turn: 24, and past 50 materials 1200 / n
/// (at least 8), since each left-out material costs one latent fit per layout and q, O(n^3) per
/// likelihood evaluation: 12 at n = 100 keeps the default run within a few minutes
/// (docs/EVALUATION.md). All n when n is smaller.
int automatic_held_out(std::size_t materials);

/// The six layout transforms: linear, cbrt, log, each plain and cosine-weighted.
std::vector<LayoutTransform> all_layouts();

struct StudyOptions {
  std::vector<int> dims{2, 3, 5, 8};              ///< latent dimensions q
  std::vector<LayoutTransform> layouts = all_layouts();
  int materials = 0;         ///< materials left out in turn (0 = all), spread evenly by index
  int pairs = 20;            ///< material pairs for latent paths (0 = none)
  int path_segments = 8;     ///< segments per latent path
  /// Subsample the values for perceptual distances: every value_stride-th (1 = all). 0: chosen
  /// so that the pass compares at most `compared_values_budget` values in all (tables x values
  /// per table), which keeps the default run to a minute or two whatever the database's size.
  int value_stride = 0;
  double compared_values_budget = 1e9;
  int projection_starts = 3; ///< multi-start count of the projection
  FitOptions fit{};
  std::size_t block_columns = 0;  ///< 0: by the number of materials (manifold/gram.h)
  unsigned seed = 1;         ///< pair selection
};

/// One left-out material under one configuration.
struct LooEntry {
  int material = -1;
  BrdfDistance gp;       ///< matlas: projection onto the map fitted without it
  BrdfDistance pca;      ///< mean + q components fitted without it
  BrdfDistance nearest;  ///< the closest remaining material (by the cube-root distance)
  int nearest_material = -1;
  double gram_residual = 0;  ///< projection residual in the layout space (relative)
};

/// One latent path.
struct PathEntry {
  int a = -1, b = -1;
  double latent_distance = 0;
  BrdfDistance ends;                ///< distance between the two materials
  std::vector<BrdfDistance> steps;  ///< between consecutive samples (path_segments of them)
};

/// Results for one (layout, q).
struct ConfigResult {
  LayoutTransform layout;
  int dim = 0;
  double log_likelihood = 0;
  Eigen::MatrixXd latent;  ///< n x q, fitted on all materials
  std::vector<LooEntry> loo;
  std::vector<PathEntry> paths;
  /// Spearman correlation of latent distance with the cube-root distance over all material pairs.
  double spearman_pairs = 0;
  /// Spearman correlation of latent step length with the cube-root distance of the step, over
  /// every step of every path.
  double spearman_steps = 0;
  /// Mean over paths of (sum of step distances) / (end distance): 1 for a perceptually straight path.
  double path_length_ratio = 0;
  /// Mean over paths of (largest step) / (mean step): 1 for perceptually uniform speed.
  double path_step_unevenness = 0;
  double loo_gp_cbrt = 0, loo_gp_rmse = 0;    ///< means over left-out materials
  double loo_pca_cbrt = 0, loo_pca_rmse = 0;
  double loo_nearest_cbrt = 0, loo_nearest_rmse = 0;
  double fit_seconds = 0;
};

struct StudyResult {
  std::vector<std::string> names;
  std::size_t kept_columns = 0;
  std::size_t compared_values = 0;   ///< values per perceptual distance
  int value_stride = 1;              ///< the stride used (options.value_stride, or the one chosen)
  Eigen::MatrixXd material_cbrt;     ///< n x n cube-root distances between the materials
  Eigen::MatrixXd material_rmse;     ///< n x n cosine-RMSE distances
  std::vector<ConfigResult> configs; ///< layouts x dims, layout-major
  std::vector<int> dims;
  std::vector<LayoutTransform> layouts;
  /// The layout with the lowest leave-one-out cube-root error averaged over the dims, and why.
  LayoutTransform recommended;
  std::string recommendation;
  double gram_seconds = 0, fit_seconds = 0, pass_seconds = 0;

  const ConfigResult& config(const LayoutTransform& layout, int dim) const;
};

/// Runs the study. Progress through `progress`; throws matlas::Error on bad options.
///
/// Split across processes (`mpirun -np P matlas evaluate`, core/communicator.h; every rank calls
/// this with its communicator): the Gram passes and the perceptual distances' pass read a share
/// of every file's values each and add up their sums (manifold/gram_reduce.h,
/// reduce_combinations), the latent fits are shared out by job and exchanged; every rank returns
/// the whole result, the same to rounding as one process's.
StudyResult run_layout_study(const MaterialSet& set, const StudyOptions& options,
                             ProgressSink& progress = null_progress(), Communicator& comm = serial_communicator());

/// The material pairs used for paths: `count` distinct pairs drawn deterministically from seed.
std::vector<std::pair<int, int>> choose_pairs(int n, int count, unsigned seed);

}  // namespace matlas::eval
