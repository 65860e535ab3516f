#pragma once
// Combination: a point of a model (a table, an image, a coefficient set: anything linear in the
// table) as an affine combination of the mean and the n inputs,
//
//     m = c_0 mean + sum_i c_i z_i,   c = (c_0, w_1, ..., w_n),   c_0 = 1 - sum_i w_i,
//
// which is m = mean + sum_i w_i (z_i - mean) (manifold/model.h). The weights w (n values, any sum)
// and the coefficients c over (mean, inputs) (n + 1 values, sum 1) are two views of one
// combination. When the mean is the inputs' own average (mean = sum_i z_i / n), m is also an affine
// combination of the inputs alone, with the affine coefficients g = w + c_0 / n (sum g = 1).
//
// The mean's weight c_0 is computed here and nowhere else, with one snapping rule: it is exactly 0
// when |1 - sum w| <= kSnap (1e-12). Every convex combination and every unit vector then reads the
// inputs alone, so an exact zero of the inputs stays an exact zero (not -1e-16 times the mean), and
// g = w exactly.
#include <Eigen/Core>

namespace matlas {

class Combination {
public:
  /// |1 - sum w| at or below which the mean's weight is exactly 0.
  static constexpr double kSnap = 1e-12;

  /// The mean's weight of the weights w: 1 - sum w, or exactly 0 within kSnap of 0.
  static double mean_weight(const Eigen::Ref<const Eigen::VectorXd>& w);

  /// The combination of the inputs' weights w (length n).
  explicit Combination(Eigen::VectorXd weights);
  /// The combination of the coefficients c = (c_0, w) over (mean, inputs) (length n + 1, sum 1 up
  /// to kSnap: a failure is a bug, MATLAS_CHECK). c_0 is computed again from w.
  static Combination from_coefficients(const Eigen::Ref<const Eigen::VectorXd>& c);

  int count() const { return static_cast<int>(w_.size()); }  ///< n
  const Eigen::VectorXd& weights() const { return w_; }      ///< w
  double mean_weight() const { return mean_weight_; }         ///< c_0
  /// c = (c_0, w_1, ..., w_n) over (mean, inputs).
  Eigen::VectorXd coefficients() const;
  /// g = w + c_0 / n over the inputs alone, for a mean that is the inputs' average (n >= 1).
  Eigen::VectorXd affine() const;

private:
  Eigen::VectorXd w_;
  double mean_weight_;
};

}  // namespace matlas
