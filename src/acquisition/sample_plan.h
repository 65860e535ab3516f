#pragma once
// Which directions to measure (docs/ACQUISITION.md): a greedy Bayesian experimental design over
// the map's inputs.
//
// In the layout's space the inputs' values at the candidate directions are a random vector
// t = mu + G a (a ~ N(0, I_r)): G holds the r leading principal components of the inputs (each
// weighted by p_i, uniform for a fresh plan), so a material of the database is one draw. A
// measurement of candidate c observes its three rows G_c a with noise that grows with each row's
// magnitude (as the square root: between a share of the value and a constant). The plan picks,
// one direction at a time, the candidate with the largest information gain
//     log det(I_3 + Sigma_c^-1/2 G_c P G_c^T Sigma_c^-1/2)
// (P the posterior covariance of a given the directions chosen so far, updated by Woodbury),
// i.e. the direction where the materials still in play disagree most in the directions not yet
// pinned down. This is the map's version of the condition-number design of Nielsen et al. 2015
// for PCA (which the evaluation keeps as the baseline, eval/sparse_study.h): the same greedy
// spirit, but with the prior the database gives to each component instead of treating them
// alike. The sequential mode conditions on the directions already measured and weights the
// inputs by how well each explains the values measured so far, so the next direction separates
// the materials that are still plausible.
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "acquisition/sparse_fit.h"
#include "brdf/merl_grid.h"
#include "formats/sample_file.h"

namespace matlas::acquisition {

/// Candidate directions: bin centres of the MERL grid on a stratified lattice with theta_i and
/// theta_o below 80 degrees (grazing directions are rarely measurable).
struct PlanCandidates {
  std::vector<MeasuredSample> directions;  ///< C unmeasured direction pairs (phi_h = 0)
  std::vector<std::size_t> bins;           ///< C flat bin indices
};
/// Every theta_h_step-th theta_h bin, theta_d_step-th theta_d bin and phi_d_step-th phi_d bin
/// (starting at the first), kept where both directions are within 80 degrees of the normal. A step of 0
/// gives about 30, 18 and 18 positions (3, 5 and 10 on MERL's 90 x 90 x 180 grid: about 5,000
/// candidates), and every bin of grids that small.
PlanCandidates plan_candidates(const MerlDims& dims, int theta_h_step = 0, int theta_d_step = 0,
                               int phi_d_step = 0);

/// What the design sees: the inputs' physical values at the candidates.
struct PlanSpace {
  Eigen::MatrixXd values;  ///< 3C x n, row 3c + channel
  Eigen::VectorXd cosine;  ///< C: cos(theta_i) cos(theta_o) of each candidate
};

struct PlanOptions {
  LayoutTransform transform{LayoutTransform::Map::cube_root, true};
  int rank = 40;       ///< principal components kept (at most n - 1)
  /// Measurement noise in the transform's space, relative to sqrt(row RMS x typical RMS).
  double noise = 0.05;
};

struct Plan {
  std::vector<int> chosen;    ///< candidate indices, in the order picked
  std::vector<double> gain;   ///< information gain of each pick (nats)
  /// Share of the inputs' variance at the candidates (in the transform's space) left unexplained
  /// after each pick: 1 before any, towards 0.
  std::vector<double> remaining;
};

/// Picks `count` candidates. `material_weight`: n non-negative weights of the inputs (uniform:
/// a fresh plan); `measured`: rows already measured (their inputs' values and cosines; may be
/// null), conditioned on first; `excluded`: candidates never picked (those already measured: the
/// gain of measuring a direction again is only the noise averaged down, which a plan should not
/// spend samples on). Throws matlas::Error on mismatched shapes or count < 1.
Plan plan_directions(const PlanSpace& space, const Eigen::VectorXd& material_weight, const SampleRows* measured,
                     int count, const PlanOptions& options = {}, std::span<const int> excluded = {});

/// Weights of the inputs for a sequential plan from each input's loss alone on the samples
/// measured so far (SparseFit::input_loss): p_i = exp(-(L_i - min L) / T), with T set so that
/// the effective number of inputs (sum p)^2 / sum p^2 is `effective` (clamped to [1, n]).
Eigen::VectorXd plausible_inputs(const Eigen::VectorXd& input_loss, double effective);

}  // namespace matlas::acquisition
