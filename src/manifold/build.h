#pragma once
// Building a manifold model from a MaterialSet in one streaming pass over the files:
//   the pass: validity mask (a column is kept only if every material is measured there), mean,
//           centred Gram S = (Z - mean)(Z - mean)^T of the data (double) and of the layout
//           transform of the data (used to place the latent points), albedo curves, source file
//           hashes; the inputs of the kept columns, column-interleaved, go straight into the
//           model file as each block is read (the stored tensor does not depend on the layout);
//   latent placement: PCA initialisation, then maximisation of the GP log-likelihood;
//   finishing: the small tensors and the header are written into the space left for them.
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/communicator.h"
#include "core/progress.h"
#include "gp/optimize.h"
#include "gp/sparse_optimize.h"
#include "manifold/gram.h"
#include "manifold/interpolation.h"
#include "manifold/material_set.h"

namespace matlas {

enum class Storage { f32, f16 };

struct BuildOptions {
  int dim = 2;                       ///< latent dimension q (1..10)
  double nugget = 1e-4;              ///< delta on the diagonal of K
  /// Data transform used to place the latent points (and the metric of the convex interpolation).
  /// Default: cosine-weighted cube root, a perceptual metric (docs/EVALUATION.md).
  LayoutTransform layout{LayoutTransform::Map::cube_root, true};
  /// Priors on the latent points (repulsion between points, bounded extent): the layout spreads
  /// materials the likelihood alone would merge (docs/GP.md, "Spreading the layout").
  gp::LatentPrior prior = gp::LatentPrior::spread();
  /// Optimiser and its limits; starts 0 (the default) means default_starts(dim).
  gp::OptimizeOptions optimize = default_optimize();
  /// The sparse latent optimisation (`--sparse-inducing M`, `--sparse-rank R`; docs/GP.md, "Sparse
  /// latent optimisation"): off by default (the exact likelihood); for databases past a few thousand
  /// materials, where an exact evaluation costs O(n^3). Never switched on automatically.
  gp::SparseOptions sparse{};
  /// Interpolation mode stored in the model (queries may override it).
  Interpolation interpolation = Interpolation::convex;
  /// Relative ridge of the convex mode's metric (gp/convex_weights.h).
  double convex_ridge = 1e-2;
  Storage storage = Storage::f32;    ///< precision of the stored centred data
  /// Columns per streamed block (all n materials); 0: by the number of materials
  /// (default_block_columns in manifold/gram.h: 4096 up to 511 materials, wider from 512 on).
  std::size_t block_columns = 0;

  /// The settings of Soler et al. 2018 (`matlas build --preset paper`): the plain likelihood
  /// (no latent priors) of the linear data with nugget 1e-4 and l = 1, Hooke-Jeeves from one
  /// start, GP interpolation.
  static BuildOptions paper_preset();
  /// Optimiser starts when none are named (optimize.starts 0): 3 for q <= 2, where the
  /// likelihood has several maxima, else 1.
  static int default_starts(int dim) { return dim <= 2 ? 3 : 1; }
  /// gp::OptimizeOptions' defaults with starts 0 (default_starts of the dimension), the iteration
  /// limit and the coarse stage automatic (by the number of materials).
  static gp::OptimizeOptions default_optimize() {
    gp::OptimizeOptions o;
    o.starts = 0;
    o.max_iterations = -1;  // automatic (gp::OptimizeOptions::resolved): shorter from 500 materials on
    o.coarse = -1;         // automatic: coarse-to-fine from 500 materials on
    return o;
  }
  /// `o` with starts 0 resolved for latent dimension `dim`.
  static gp::OptimizeOptions resolved(gp::OptimizeOptions o, int dim) {
    if (o.starts == 0) o.starts = default_starts(dim);
    return o;
  }
};

struct BuildReport {
  std::size_t kept_columns = 0, dropped_columns = 0;
  double log_likelihood = 0;
  gp::OptimizeResult optimization;
  /// The pass over the files (and the data written), the latent placement, the rest of the file.
  double pass_seconds = 0, optimize_seconds = 0, finish_seconds = 0;
  PassSteps pass_steps;  ///< where the pass's time went
  /// Relative L2 error of the stored (rounded) data against the double data: float32 or float16.
  double storage_relative_error = 0;
  /// A distributed build's pass on this rank: its share, waiting for the other ranks to finish
  /// theirs, adding up the Grams and gathering on rank 0, placing the ranks' data in the model
  /// (each rank copies its share; rank 0 waits for them).
  double share_seconds = 0, wait_seconds = 0, reduce_seconds = 0, place_seconds = 0;
};

/// The latent placement of a build, and of the evaluation's fits: from PCA, the MAP optimisation
/// of the GP likelihood of `problem` (its Gram, columns, kernel and priors) in q dimensions, exact,
/// or sparse when `sparse` is enabled (gp/sparse_optimize.h; then `optimize` must be L-BFGS).
gp::OptimizeResult place_latent_points(const gp::LikelihoodProblem& problem, int q, const gp::OptimizeOptions& optimize,
                                       const gp::SparseOptions& sparse, ProgressSink& progress = null_progress());

/// Builds a model and writes it atomically to `output`.
///
/// With a communicator of P > 1 ranks (`mpirun -np P matlas build`; every rank calls this with
/// the same set, options and output, on storage every rank sees), rank r reads only its share of
/// the column blocks of every file (gram.h's PassShare), the ranks add up their Gram matrices and
/// albedo curves (gram_reduce.h) and write their data into the one model file (data_shares.h);
/// rank 0 places the latent points and writes the rest. The model is the single-process one
/// bit for bit (the Gram sums are compensated: gram_update.h) but for the albedo curves' last
/// bits and the source hashes (of the ranks' byte ranges). An error on any rank is thrown on
/// every rank.
BuildReport build_model(const MaterialSet& set, const BuildOptions& options,
                        const std::filesystem::path& output, ProgressSink& progress = null_progress(),
                        Communicator& comm = serial_communicator());

}  // namespace matlas
