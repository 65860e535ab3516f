#pragma once
// Coarse-to-fine latent placement for large databases (docs/GP.md, "Coarse-to-fine placement"):
// L-BFGS needs thousands of iterations at n = 1000 (exact) or 10,000 (sparse) because it moves
// every point at once, and the long-wavelength structure of the map settles slowest. A subset of the
// items is placed first (a smaller problem of the same kind, cheaper per iteration and quicker to
// settle), every other item is put where its nearest subset items in the data lie, and the whole
// layout is then refined from there.
#include <Eigen/Core>
#include <chrono>
#include <cstdint>
#include <vector>

#include "gp/likelihood.h"
#include "gp/optimize.h"
#include "gp/sparse_likelihood.h"

namespace matlas::gp {

/// `count` of the n items, chosen at random without replacement (seeded, so deterministic), in
/// increasing order; all of them when count >= n. Throws matlas::Error for count < 1.
std::vector<Eigen::Index> coarse_subset(Eigen::Index n, int count, std::uint64_t seed = 1);

/// The sparse problem of the rows `rows` of p: their rows of the data factor, the residual's
/// share of those items (residual x rows / n, the residual being spread evenly), the same columns,
/// kernel and priors.
SparseProblem subset_problem(const SparseProblem& p, const std::vector<Eigen::Index>& rows);

/// A layout of all n items from the layout `placed` of the items `rows`: those keep their points;
/// every other item goes to the mean of the points of its `neighbours` nearest items among `rows`
/// (distances between rows of the data factor), weighted by inverse distance, plus a deterministic
/// offset of `jitter` times the RMS radius of `placed` (coinciding points would never separate:
/// the repulsion's gradient vanishes there). Throws matlas::Error for inconsistent shapes or
/// neighbours < 1.
Eigen::MatrixXd interpolate_layout(const LowRankGram& data, const std::vector<Eigen::Index>& rows,
                                   const Eigen::MatrixXd& placed, int neighbours = 4, double jitter = 1e-3);

/// The same with the distances of the n x n Gram matrix S (|z_i - z_j|^2 = S_ii + S_jj - 2 S_ij),
/// for the exact placement.
Eigen::MatrixXd interpolate_layout(const Eigen::MatrixXd& gram, const std::vector<Eigen::Index>& rows,
                                   const Eigen::MatrixXd& placed, int neighbours = 4, double jitter = 1e-3);

/// The exact problem of the rows `rows` of p: their rows and columns of the Gram, the same
/// columns, kernel and priors.
LikelihoodProblem subset_problem(const LikelihoodProblem& p, const std::vector<Eigen::Index>& rows);

/// The refinement's options after a coarse stage that took `spent` seconds: one start, all at
/// once, what is left of the time limit.
OptimizeOptions refinement_options(const OptimizeOptions& o, double spent);

/// The refinement's result counted with its coarse stage's: iterations and evaluations of both,
/// the coarse stage's winning start, the seconds since `begin`.
OptimizeResult with_coarse_stage(OptimizeResult refined, const OptimizeResult& coarse,
                                 std::chrono::steady_clock::time_point begin);

}  // namespace matlas::gp
