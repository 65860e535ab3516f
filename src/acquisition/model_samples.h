#pragma once
// Sparse samples against a model file: the rows of a fit read from the model's stored inputs, the
// model as a map to search, and the fit and the plan of a model (`matlas fit-samples`,
// `matlas sample-plan`, the Python functions and the server's upload).
#include <string>
#include <vector>

#include "acquisition/sample_plan.h"
#include "acquisition/sparse_fit.h"
#include "formats/sample_file.h"
#include "manifold/model.h"

namespace matlas::acquisition {

/// The transform the model's latent points were placed with (metadata "layout_transform";
/// cosine-cbrt for models without it).
LayoutTransform model_transform(const Model& model);

/// The rows of the measured samples (three per sample, in order; the rows' `sample` indexes
/// `samples`), each input's value read from its bin (MERL's nearest-bin rule). A channel whose
/// bin is not a kept column of the model (no input measured there) has no row; such samples are
/// listed in `unusable` ("line 7: the model has no data at this direction").
SampleRows model_rows(const Model& model, const std::vector<MeasuredSample>& samples,
                      std::vector<std::string>* unusable = nullptr);

/// The model as a map: its latent points, raw coefficients in its interpolation mode, variance.
MapView model_map(const Model& model);

/// What a fit of a model answers, beside SparseFit: the weights and table of the point.
struct ModelFit {
  SparseFit fit;
  /// The model's weights of the answer (Model::table of them is the fitted table): Model::weights
  /// at fit.x, or the combination's coefficients when the combination stage was chosen.
  Eigen::VectorXd weights;
  std::vector<std::string> unusable; ///< samples without rows (see model_rows)
  /// The rows fitted (SparseFit's per-row figures follow them); `sample` indexes the measured
  /// samples among those given, in order.
  SampleRows rows;
};
/// Fits measured samples (the unmeasured ones are ignored) on the model. Throws matlas::Error
/// when fewer than q + 1 usable samples remain.
ModelFit fit_samples(const Model& model, const std::vector<MeasuredSample>& samples,
                     const SparseFitOptions& options);

/// The plan of `count` directions for the model: a fresh one when `measured` holds no values,
/// else the next directions given those samples (conditioned on their directions, the inputs
/// weighted by how well each explains them: plausible_inputs with n / 4 effective inputs, at
/// least 2q + 2). Returns the chosen candidates as unmeasured samples, with the plan's figures.
struct ModelPlan {
  std::vector<MeasuredSample> directions;
  Plan plan;
  int conditioned_on = 0;  ///< measured samples taken into account
};
ModelPlan plan_samples(const Model& model, int count, const std::vector<MeasuredSample>& measured,
                       const PlanOptions& options);

}  // namespace matlas::acquisition
