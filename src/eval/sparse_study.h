#pragma once
// The leave-one-out study of sparse reconstruction (docs/ACQUISITION.md, `matlas evaluate
// --sparse`): for each material h of a database, the map is fitted without h (eval/latent_fit.h,
// as a build places it), K samples of h are taken at directions planned for that map
// (acquisition/sample_plan.h) or at random, fitted (acquisition/sparse_fit.h), and the
// reconstruction is measured against h's full table; beside it, the PCA baseline of Nielsen et al.
// 2015 (eval/sparse_pca.h) fitted without h, with its condition-number directions and at the same
// random directions, for the same K.
//
// Directions are drawn from one pool of candidates (a random subset of the plan's lattice of bin
// centres, acquisition/plan_candidates), and a sample's values are h's values at the candidate's
// bin, as a measurement at the bin centre would read them. The error is the evaluation's
// cosine-weighted cube-root distance (eval/brdf_distance.h) over a random subsample of the
// table's values above the horizon (the subsample's size is in the result; 200,000 of 4.4 million
// by default), so the study needs one pass over the files and no table in memory.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/progress.h"
#include "eval/latent_fit.h"
#include "manifold/layout_transform.h"
#include "manifold/material_set.h"

namespace matlas::eval {

struct SparseStudyOptions {
  std::vector<int> counts{5, 10, 20, 40, 80};  ///< K, samples per material
  int dim = 2;                                  ///< q of the maps
  LayoutTransform layout{LayoutTransform::Map::cube_root, true};
  FitOptions fit;                  ///< how each map is fitted (convex interpolation by default)
  int candidates = 1500;           ///< the pool of candidate directions
  int evaluation_values = 200000;  ///< values compared per reconstruction
  int materials = 0;               ///< materials left out in turn (0 = all), spread evenly by index
  /// The robustness test: at K = robustness_count planned samples, this share of the samples
  /// multiplied by outlier_factor.
  int robustness_count = 20;
  double outlier_share = 0.1;
  double outlier_factor = 10;
  /// The PCA baseline's ridge: each K reports the best of these (mean error over materials), a
  /// choice made with the answers, in the baseline's favour.
  std::vector<double> pca_ridges{1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1};
  int pca_condition_components = 20;  ///< components in the condition number (at most K of them)
  unsigned seed = 1;
};

/// One method at one K: the error of each left-out material's reconstruction.
struct SparseResult {
  std::string method;         ///< "matlas-planned", "matlas-random", "pca-condition", "pca-random"
  int count = 0;              ///< K
  std::vector<double> error;  ///< per left-out material: cube-root distance to its table
  double mean = 0, median = 0;
  double ridge = 0;           ///< PCA: the ridge chosen
};

struct SparseStudy {
  std::vector<std::string> materials;  ///< the materials left out, in order
  int inputs = 0;                      ///< materials per map (n - 1)
  int candidates = 0, evaluation_values = 0, dim = 0;
  std::string layout;
  std::vector<SparseResult> results;
  /// Robustness (matlas, planned, K = robustness_count): mean error clean, with the outliers
  /// (robust loss), and with the outliers under least squares.
  int robustness_count = 0;
  double clean = 0, corrupted = 0, corrupted_least_squares = 0;
  /// The nearest-material reference: each material's nearest other material (the best any
  /// "pick one input" method could do), mean error.
  double nearest_input = 0;
  double fit_seconds = 0;  ///< mean seconds of one fit at the largest K
  double seconds = 0;      ///< the whole study
  const SparseResult& find(const std::string& method, int count) const;
};

/// Runs the study. Throws matlas::Error on bad options (counts < 1 or more than the candidates).
SparseStudy run_sparse_study(const MaterialSet& set, const SparseStudyOptions& options,
                             ProgressSink& progress = null_progress());

/// The study as JSON (every per-material error included).
nlohmann::json sparse_study_json(const SparseStudy& study);

}  // namespace matlas::eval
