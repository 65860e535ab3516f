#pragma once
// The weight of the mean in a model's tables, m(x) = (1 - sum w) mean + sum_i w_i z_i.
#include <Eigen/Core>

namespace matlas {

/// 1 - sum w, or exactly 0 when the weights sum to 1 up to rounding (|1 - sum w| <= 1e-12): every
/// convex combination and unit vector then reads the stored inputs alone, so an exact zero of the
/// inputs stays an exact zero (not -1e-16 times the mean).
double mean_weight(const Eigen::Ref<const Eigen::VectorXd>& w);

}  // namespace matlas
