#pragma once
// PCA initialisation of the latent points.
#include <Eigen/Core>
#include <functional>

#include "gp/likelihood.h"

namespace matlas::gp {

/// PCA initialisation: the top-q principal component scores of the data (eigenvectors u_k of the
/// centred Gram S scaled by sqrt(lambda_k)), multiplied by one global factor a chosen to maximise
/// log_likelihood(p, a X): a coarse log-spaced scan over 6 decades around the scale where the
/// points have unit RMS radius, then golden-section refinement on log a. Eigenvector signs are
/// fixed (largest-magnitude entry positive), so the result is deterministic and does not change
/// when the data are scaled. Returns n x q. Throws matlas::Error for q < 1 or a malformed problem.
/// With search_scale false, a is the factor that gives the points unit RMS radius (in lengthscale
/// units), without the search: for a coarse-to-fine placement, which scales its subset itself.
Eigen::MatrixXd pca_initialization(const LikelihoodProblem& p, int q, bool search_scale = true);

/// The scan-and-golden-section search used above: the factor a > 0 maximising the likelihood of
/// a * X, searched on log a within [a_min, a_max]: `scan` log-spaced values (at least 2), then
/// golden sections about the best until the interval in log a is below `tolerance`.
double best_scale_factor(LikelihoodEvaluator& evaluator, const Eigen::MatrixXd& X, double a_min, double a_max,
                         int scan = 25, double tolerance = 1e-6);
/// The same search for any objective value(a X) (the sparse objective's initialisation); a value
/// that throws matlas::Error counts as -infinity.
double best_scale_factor(const std::function<double(const Eigen::MatrixXd&)>& value, const Eigen::MatrixXd& X,
                         double a_min, double a_max, int scan = 25, double tolerance = 1e-6);

}  // namespace matlas::gp
