#include "core/combination.h"

#include <cmath>
#include <utility>

#include "core/check.h"

namespace matlas {

double Combination::mean_weight(const Eigen::Ref<const Eigen::VectorXd>& w) {
  const double rest = 1.0 - w.sum();
  return std::abs(rest) <= kSnap ? 0.0 : rest;
}

Combination::Combination(Eigen::VectorXd weights) : w_(std::move(weights)), mean_weight_(mean_weight(w_)) {}

Combination Combination::from_coefficients(const Eigen::Ref<const Eigen::VectorXd>& c) {
  MATLAS_CHECK_GE(c.size(), 1);
  Combination out(c.tail(c.size() - 1));
  MATLAS_CHECK(std::abs(c[0] - out.mean_weight_) <= kSnap, "the coefficients sum to 1");
  return out;
}

Eigen::VectorXd Combination::coefficients() const {
  Eigen::VectorXd c(w_.size() + 1);
  c[0] = mean_weight_;
  c.tail(w_.size()) = w_;
  return c;
}

Eigen::VectorXd Combination::affine() const {
  MATLAS_CHECK_GE(w_.size(), 1);
  return w_.array() + mean_weight_ / static_cast<double>(w_.size());
}

}  // namespace matlas
