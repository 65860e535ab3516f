// Trustworthiness (Venna & Kaski 2001) of a latent layout against given distances: 1 for a layout
// that keeps every neighbourhood, and a hand-computed value for a layout with two points swapped.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "core/error.h"
#include "eval/manifold_quality.h"

namespace matlas::eval {
namespace {

Eigen::MatrixXd squared_distances(const Eigen::VectorXd& p) {
  const auto n = p.size();
  Eigen::MatrixXd d(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) d(i, j) = (p[i] - p[j]) * (p[i] - p[j]);
  return d;
}

TEST(Trustworthiness, IsOneWhenTheLayoutKeepsEveryNeighbourhood) {
  Eigen::VectorXd p(7);
  p << 0, 1, 3, 6, 10, 15, 21;
  // Any scale of the latent layout keeps the neighbourhoods.
  const Eigen::MatrixXd latent = 0.25 * p;
  for (int k = 1; k <= 2; ++k) EXPECT_DOUBLE_EQ(trustworthiness(squared_distances(p), latent, k), 1.0) << k;
}

TEST(Trustworthiness, MatchesAHandComputedSwap) {
  // True positions 0 1 3 6 10 15 on a line; the layout swaps the two ends. With k = 1 the
  // intrusions are: point 0 (at 15) has latent neighbour 4, true rank 4; point 1 has 5, rank 5;
  // point 5 (at 0) has 1, rank 4. Penalty (4-1) + (5-1) + (4-1) = 10;
  // T = 1 - 2 / (n k (2n - 3k - 1)) * 10 = 1 - 20 / 48.
  Eigen::VectorXd p(6);
  p << 0, 1, 3, 6, 10, 15;
  Eigen::VectorXd latent = p;
  std::swap(latent[0], latent[5]);
  EXPECT_NEAR(trustworthiness(squared_distances(p), latent, 1), 1.0 - 20.0 / 48.0, 1e-12);
}

TEST(Trustworthiness, RefusesANeighbourhoodTooLargeForTheSet) {
  Eigen::VectorXd p(6);
  p << 0, 1, 3, 6, 10, 15;
  EXPECT_THROW(trustworthiness(squared_distances(p), p, 3), Error);
  EXPECT_THROW(trustworthiness(squared_distances(p), p, 0), Error);
}

}  // namespace
}  // namespace matlas::eval
