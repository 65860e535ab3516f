#pragma once
// Convex interpolation weights: the GP's affine combination of the inputs projected onto the
// probability simplex in the metric of the data.
//
// The GP posterior mean is an affine combination of the inputs, m(x) = sum_i g_i(x) z_i with
// sum_i g_i = 1 (g = w + (1 - sum w) / n for the weights w = K^-1 k(x) of the centred data), and
// its coefficients can be negative: m(x) can then have negative values and more energy than any
// input. ConvexProjection replaces g by the closest convex combination in the metric A,
//
//     c(g) = argmin_{c >= 0, sum c = 1} (c - g)^T A (c - g),   A = S / (tr S / n) + ridge I,
//
// with S the centred Gram matrix of the inputs (in the space used to place them). Properties, all
// tested:
// - convex: c >= 0 and sum c = 1, so every value of m(x) lies between the inputs' smallest and
//   largest values at that bin: no negative value (for non-negative inputs), reciprocity kept, and
//   any linear functional (directional albedo, an image) at most the inputs' largest;
// - exact at the data: g = e_i is already convex, so c = e_i;
// - continuous (Lipschitz): the projection onto a convex set in the A-norm is non-expansive in
//   that norm, |c(g) - c(g')|_A <= |g - g'|_A, and ridge > 0 makes A positive definite;
// - where g is convex already (near the data, most of the map), c = g: the GP unchanged.
// The quadratic programme (n variables, one equality, n bounds) is solved exactly by a primal
// active-set method (Nocedal & Wright, Numerical Optimization, Algorithm 16.3), started from the
// clipped and renormalised g; it ends in a few iterations since the solution is sparse.
#include <Eigen/Core>

namespace matlas::gp {

class ConvexProjection {
public:
  /// Default relative ridge: A = S / (tr S / n) + kDefaultRidge I.
  static constexpr double kDefaultRidge = 1e-2;

  /// gram: the centred Gram matrix S (n x n, symmetric PSD); ridge > 0 relative to tr(S)/n.
  /// Throws matlas::Error if S is not square and finite or ridge is not > 0.
  explicit ConvexProjection(const Eigen::MatrixXd& gram, double ridge = kDefaultRidge);

  int count() const { return static_cast<int>(A_.rows()); }
  double ridge() const { return ridge_; }
  const Eigen::MatrixXd& metric() const { return A_; }  ///< A

  /// c(g) for affine coefficients g (length n, sum 1 up to rounding; throws otherwise).
  Eigen::VectorXd project(const Eigen::Ref<const Eigen::VectorXd>& g) const;

  /// The convex weights for the GP weights w of the centred data: c(w + (1 - sum w) / n).
  Eigen::VectorXd from_centred(const Eigen::Ref<const Eigen::VectorXd>& w) const;

private:
  Eigen::MatrixXd A_;
  double ridge_;
};

/// The affine coefficients g = w + (1 - sum w) / n of the GP weights w of the centred data.
Eigen::VectorXd affine_coefficients(const Eigen::Ref<const Eigen::VectorXd>& w);

}  // namespace matlas::gp
