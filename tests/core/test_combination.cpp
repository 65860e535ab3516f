#include <gtest/gtest.h>

#include <random>

#include "core/check.h"
#include "core/combination.h"

namespace matlas {
namespace {

Eigen::VectorXd random_weights(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd w(n);
  for (int i = 0; i < n; ++i) w[i] = normal(rng);
  return w;
}

TEST(Combination, TheMeanTakesWhatTheInputsLeave) {
  const Eigen::VectorXd w = random_weights(7, 1);
  const Combination c(w);
  EXPECT_EQ(c.count(), 7);
  EXPECT_EQ(c.weights(), w);
  EXPECT_DOUBLE_EQ(c.mean_weight(), 1.0 - w.sum());
  EXPECT_EQ(Combination::mean_weight(w), c.mean_weight());
  EXPECT_DOUBLE_EQ(Combination(Eigen::VectorXd::Zero(4)).mean_weight(), 1.0);  // the mean alone
}

TEST(Combination, CoefficientsOverMeanAndInputsSumToOne) {
  const Eigen::VectorXd w = random_weights(5, 2);
  const Eigen::VectorXd c = Combination(w).coefficients();
  ASSERT_EQ(c.size(), 6);
  EXPECT_EQ(c[0], Combination::mean_weight(w));
  EXPECT_EQ(c.tail(5), w);
  EXPECT_NEAR(c.sum(), 1.0, 1e-14);
}

TEST(Combination, RoundTripsWeightsToCoefficientsAndBack) {
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const Eigen::VectorXd w = random_weights(1 + static_cast<int>(seed % 9), seed);
    const Combination there(w);
    const Combination back = Combination::from_coefficients(there.coefficients());
    EXPECT_EQ(back.weights(), w);  // w -> c -> w exactly
    EXPECT_EQ(back.mean_weight(), there.mean_weight());
    EXPECT_EQ(back.coefficients(), there.coefficients());  // c -> w -> c exactly
  }
}

TEST(Combination, CoefficientsThatDoNotSumToOneAreABug) {
  Eigen::VectorXd c(3);
  c << 0.5, 0.5, 0.5;
  EXPECT_THROW(Combination::from_coefficients(c), InternalError);
}

TEST(Combination, AffineCoefficientsOverTheInputsAlone) {
  // With mean = sum z_i / n: c_0 mean + sum w_i z_i = sum (w_i + c_0 / n) z_i.
  const Eigen::VectorXd w = random_weights(6, 3);
  const Combination c(w);
  const Eigen::VectorXd g = c.affine();
  EXPECT_NEAR(g.sum(), 1.0, 1e-14);
  Eigen::MatrixXd z = Eigen::MatrixXd::Random(6, 10);  // an input per row
  const Eigen::RowVectorXd mean = z.colwise().mean();
  const Eigen::RowVectorXd direct = c.mean_weight() * mean + w.transpose() * z;
  EXPECT_LT((g.transpose() * z - direct).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(Combination, TheMeanWeightSnapsToZeroWithinKSnap) {
  // Weights summing to 1 up to rounding give the mean no weight at all, and are their own affine
  // coefficients: an exact zero of the inputs then stays an exact zero.
  Eigen::VectorXd w(3);
  w << 0.1, 0.2, 0.7;  // sums to 1 up to rounding
  EXPECT_EQ(Combination::mean_weight(w), 0.0);
  EXPECT_EQ(Combination(w).affine(), w);
  EXPECT_EQ(Combination::mean_weight(Eigen::VectorXd::Unit(4, 2)), 0.0);
  w << 0.5, 0.5 - 0.9 * Combination::kSnap, 0;  // within kSnap
  EXPECT_EQ(Combination::mean_weight(w), 0.0);
  w << 0.5, 0.5 + 0.9 * Combination::kSnap, 0;
  EXPECT_EQ(Combination::mean_weight(w), 0.0);
  w << 0.5, 0.5 - 2 * Combination::kSnap, 0;  // beyond it: the exact rest
  EXPECT_NEAR(Combination::mean_weight(w), 2 * Combination::kSnap, 1e-16);
  w << 0.5, 0.5 + 2 * Combination::kSnap, 0;
  EXPECT_NEAR(Combination::mean_weight(w), -2 * Combination::kSnap, 1e-16);
}

}  // namespace
}  // namespace matlas
