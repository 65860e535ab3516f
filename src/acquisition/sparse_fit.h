#pragma once
// The fit of sparse measurements on a map (docs/ACQUISITION.md): the latent point x whose table
// m(x) best explains a handful of measured values. The map is the prior: q unknowns instead of
// the table's 4.4 million values, and every answer is a table the map already holds (a convex
// combination of the inputs in the convex mode).
//
// Each measured sample gives three rows (r, g, b); a row holds the measured value y and the
// inputs' values z_i at the sample's bin, so the map predicts p(x) = sum_i c_i(x) z_i with the
// raw coefficients c(x) of the point (summing to 1). Residuals are measured in the layout's space
// (the transform that placed the latent points, applied with the sample's own cosines):
//     u = (t(p) - t(y)) / s,    loss = sum over rows of log(1 + u^2 / 2.385^2)   (Cauchy),
// with s the row's uncertainty carried into that space when the file gives one, else a robust
// scale of the residuals (1.4826 x their median absolute value at a first fit). The Cauchy loss
// bounds the pull of an outlier (its weight 1 / (1 + u^2 / 2.385^2) falls to 0), so a few corrupt
// samples do not move the point; 2.385 keeps 95 % of least squares' efficiency on Gaussian noise.
//
// The search: the loss of every input alone (x = x_i, where m(x) = z_i) ranks the starts; then
// Nelder-Mead (gp/minimize.h: the weights have kinks in the convex mode) from the latent
// points of the best inputs and the centroid. Cost: one evaluation is w(x) (O(n^2)) plus a
// (3K x n) product.
//
// Then, when the map has a metric, the combination stage: a material off the map is better
// explained by a convex combination c of all inputs than by the map's point, and samples can say
// so once there are enough of them. It minimises
//     loss(c) + lambda (c - c_x)^T A (c - c_x)   over c >= 0, sum c = 1,
// (c_x the map point's coefficients, A the map's metric: the data-space distance of the two
// tables) by Gauss-Newton with the loss's weights (each step a quadratic programme on the
// simplex, gp/convex_weights.h, then a backtracking line search on the true objective). lambda
// is chosen by 4-fold cross-validation over the samples from a grid that includes infinity (the
// map point itself): the combination is used only where held-out samples are predicted better.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "manifold/layout_transform.h"

namespace matlas::acquisition {

/// The data of a fit: measured values and the inputs' values at the same rows.
struct SampleRows {
  Eigen::MatrixXd inputs;    ///< R x n: the inputs' physical values at each row
  Eigen::VectorXd measured;  ///< R: the measured BRDF values (1/sr)
  Eigen::VectorXd sigma;     ///< R: their uncertainty (1/sr), 0 where unknown
  Eigen::VectorXd cosine;    ///< R: cos(theta_i) cos(theta_o) of the row's sample
  std::vector<int> sample;   ///< R: the index of the sample the row belongs to
  std::vector<int> channel;  ///< R: 0, 1, 2 for r, g, b
  Eigen::Index rows() const { return measured.size(); }
  /// Appends the three rows of one sample: `values` is 3 x n (the inputs at the sample's bin,
  /// per channel), y and sigma its measurement.
  void add(int sample_index, const Eigen::Ref<const Eigen::MatrixXd>& values, const Eigen::Array3d& y,
           const Eigen::Array3d& s, double cosine_factor);
};

/// The map a fit searches.
struct MapView {
  Eigen::MatrixXd latent;  ///< n x q latent points of the inputs
  /// The raw coefficients (length n, summing to 1) of the table at x over the inputs.
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> coefficients;
  /// The GP predictive variance at x (0 at the data, towards 1 far from it); may be empty.
  std::function<double(const Eigen::VectorXd&)> variance;
  /// n x n metric of the combination stage (the data's Gram over its mean diagonal plus a ridge,
  /// gp::ConvexProjection::metric); empty: no combination stage.
  Eigen::MatrixXd metric;
};

struct SparseFitOptions {
  /// The space of the residuals; a model's fit uses the model's layout transform.
  LayoutTransform transform{LayoutTransform::Map::cube_root, true};
  bool robust = true;        ///< Cauchy loss (false: least squares)
  int starts = 5;            ///< inputs whose latent points start a search (plus the centroid)
  int evaluations = 0;       ///< per start; 0 = 150 (q + 1)
  bool combination = true;   ///< the combination stage (when the map has a metric)
};

struct SparseFit {
  Eigen::VectorXd x;             ///< the latent point
  /// Raw coefficients of the answer over the inputs (sum 1): the map point's, or the combination
  /// stage's when it was chosen.
  Eigen::VectorXd coefficients;
  Eigen::VectorXd map_coefficients;  ///< the map point's raw coefficients
  /// The combination stage's strength lambda relative to the loss's curvature (infinity: the map
  /// point was kept), and the held-out loss per sample of the choice.
  double combination_strength = 0;
  bool combined = false;
  Eigen::VectorXd predicted;     ///< R: m(x) at the rows (1/sr)
  Eigen::VectorXd residual;      ///< R: t(predicted) - t(measured), in the transform's space
  Eigen::VectorXd weight;        ///< R: the loss's weight of each row (1: inlier, towards 0: outlier)
  double scale = 0;              ///< the robust scale s (rows without an uncertainty)
  double loss = 0;
  double variance = 0;           ///< predictive variance at x (0 when the view has none)
  /// Covariance of x from the loss's curvature (Gauss-Newton with the rows' weights, scaled by
  /// the residuals' spread): how well the samples pin the point down.
  Eigen::MatrixXd latent_covariance;
  Eigen::VectorXd input_loss;    ///< n: the loss of each input alone (x = x_i), at the final scale
  int best_input = -1;           ///< the input that alone explains the samples best
  int evaluations = 0;           ///< loss evaluations in all
  /// Samples whose rows are all but ignored (weight < 0.1 in every channel).
  std::vector<int> outliers;
};

/// The transform t of one value f at a row with cosine factor c (signed, so a negative
/// prediction counts as the error it is).
double transform_value(const LayoutTransform& transform, double f, double c);

/// Fits the rows on the map. Throws matlas::Error when the rows do not match the map (shapes) or
/// there are fewer samples than q + 1.
SparseFit fit_rows(const MapView& map, const SampleRows& rows, const SparseFitOptions& options = {});

}  // namespace matlas::acquisition
