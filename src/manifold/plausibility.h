#pragma once
// Plausibility of an interpolated material. The GP's predictive variance says how far a point is
// from the data, but not whether its BRDF is physically plausible: between tightly clustered
// latent points of very different materials the variance is low while the weights are large and
// of mixed sign, and the table can go negative or reflect more energy than it receives
// (docs/EVALUATION.md). This probe checks the two directly, cheaply enough to colour a whole map:
//   - the fraction of negative values, estimated on a fixed, evenly spaced sample of the kept
//     columns (each value is one dot product of length n);
//   - the directional albedo range, exact by linearity from the per-material albedo curves
//     (above 1: the material gains energy at that angle; below 0: negative on average).
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace matlas {

class Model;

struct Plausibility {
  double negative_fraction = 0;  ///< share of the sampled values below zero
  double max_albedo = 0;         ///< largest directional albedo over angles and channels
  double min_albedo = 0;         ///< smallest one
  /// 0 for a plausible material, growing with the violation: negative_fraction plus how far
  /// the albedo leaves [0, 1].
  double violation() const;
};

class PlausibilityProbe {
public:
  /// Samples up to `samples` kept columns of the model, evenly spaced (deterministic).
  explicit PlausibilityProbe(const Model& model, std::size_t samples = 4096);
  Plausibility operator()(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// The same for many weight vectors (columns of W, n x m), with matrix products.
  std::vector<Plausibility> batch(const Eigen::MatrixXd& W) const;
  std::size_t samples() const { return static_cast<std::size_t>(means_.size()); }
  /// Whether every input (database material) is plausible on the probe's samples. Then so is
  /// every convex combination of them, to rounding: non-negative values and albedo within [0, 1]
  /// are convex constraints.
  bool inputs_plausible() const { return inputs_plausible_; }
  /// Whether input i is plausible on the probe's samples (values non-negative, albedo in [0, 1]).
  bool input_plausible(int i) const;
  /// Whether w is a convex combination (w >= 0, summing to 1 within 1e-9) of plausible inputs
  /// only: then its material is plausible on the samples as they are, with no product over the
  /// samples. Convex weights are sparse, so most of a convex map's cells are known this way even
  /// when some inputs are not plausible.
  bool plausible_by_construction(const Eigen::Ref<const Eigen::VectorXd>& w) const;

private:
  const Model& model_;
  Eigen::VectorXd means_;    ///< the sampled columns' means
  Eigen::MatrixXd centred_;  ///< samples x n: the stored inputs minus their column's mean
  std::vector<char> input_plausible_;  ///< per input
  bool inputs_plausible_ = false;
};

}  // namespace matlas
