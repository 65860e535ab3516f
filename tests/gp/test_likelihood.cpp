#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "core/error.h"
#include "gp/likelihood.h"
#include "gp_test_data.h"

namespace matlas::gp {
namespace {

// Independent reference: the formula with an explicit inverse and determinant.
double reference_likelihood(const LikelihoodProblem& p, const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd K = covariance_matrix(X, p.kernel);
  const double n = static_cast<double>(X.rows()), D = p.columns;
  const double t = (K.inverse() * p.gram).trace();
  return -D * std::log(K.determinant()) - n * D * std::log(t / (n * D)) - n * D;
}

// The paper's likelihood with an explicit signal variance s2 (K_s = s2 K), not profiled.
double unprofiled_likelihood(const LikelihoodProblem& p, const Eigen::MatrixXd& X, double s2) {
  const Eigen::MatrixXd Ks = s2 * covariance_matrix(X, p.kernel);
  return -p.columns * std::log(Ks.determinant()) - (Ks.inverse() * p.gram).trace();
}

LikelihoodProblem small_problem(std::uint64_t seed) {
  LikelihoodProblem p = test::problem_for(test::random_low_rank_data(12, 40, 3, seed));
  p.kernel = Kernel{1.0, 1e-3};
  return p;
}

TEST(Likelihood, MatchesTheFormulaWithExplicitInverse) {
  const LikelihoodProblem p = small_problem(1);
  const Eigen::MatrixXd X = test::random_points(12, 2, 2);
  const double L = log_likelihood(p, X);
  EXPECT_NEAR(L, reference_likelihood(p, X), 1e-9 * std::abs(L));
}

TEST(Likelihood, IsTheMaximumOverTheSignalVariance) {
  const LikelihoodProblem p = small_problem(2);
  const Eigen::MatrixXd X = test::random_points(12, 2, 3);
  const double n = 12;
  const Eigen::MatrixXd K = covariance_matrix(X, p.kernel);
  const double s2 = (K.inverse() * p.gram).trace() / (n * p.columns);
  const double L = log_likelihood(p, X);
  EXPECT_NEAR(unprofiled_likelihood(p, X, s2), L, 1e-9 * std::abs(L));
  EXPECT_LT(unprofiled_likelihood(p, X, 1.05 * s2), L);
  EXPECT_LT(unprofiled_likelihood(p, X, 0.95 * s2), L);
}

void expect_gradient_matches_finite_differences(int q, std::uint64_t seed, LatentPrior prior = {}) {
  LikelihoodProblem p = small_problem(seed);
  p.prior = prior;
  p.columns = 1000;  // a D' unlike the data width: the gradient must scale with it
  const Eigen::MatrixXd X = test::random_points(12, q, seed + 100, 0.8);
  Eigen::MatrixXd G;
  const double L = log_likelihood(p, X, &G);
  EXPECT_EQ(L, log_likelihood(p, X));  // the gradient does not change the value
  ASSERT_EQ(G.rows(), 12);
  ASSERT_EQ(G.cols(), q);
  Eigen::MatrixXd fd(12, q);
  const double h = 1e-5;
  for (int i = 0; i < 12; ++i)
    for (int d = 0; d < q; ++d) {
      Eigen::MatrixXd Xp = X, Xm = X;
      Xp(i, d) += h;
      Xm(i, d) -= h;
      fd(i, d) = (log_likelihood(p, Xp) - log_likelihood(p, Xm)) / (2 * h);
    }
  EXPECT_LT((G - fd).norm() / G.norm(), 1e-5) << "q = " << q << "\nanalytic\n" << G << "\nfd\n" << fd;
}

TEST(Likelihood, GradientMatchesCentralDifferencesQ2) { expect_gradient_matches_finite_differences(2, 10); }
TEST(Likelihood, GradientMatchesCentralDifferencesQ3) { expect_gradient_matches_finite_differences(3, 20); }

TEST(Likelihood, GradientWithPriorsMatchesCentralDifferences) {
  expect_gradient_matches_finite_differences(2, 30, LatentPrior{0.0, 0.1, 0.0, 0.6});
  expect_gradient_matches_finite_differences(4, 31, LatentPrior{0.0, 0.1, 0.0, 0.25});
  // Radius comparable to the point spacing, so the barrier is active.
  expect_gradient_matches_finite_differences(2, 32, LatentPrior{2.0, 0.5, 0.3, 1.0});
  expect_gradient_matches_finite_differences(3, 33, LatentPrior::spread());
}

TEST(Likelihood, PriorsAddTheirLogDensities) {
  // Each prior term computed independently here, in D' units like the likelihood.
  LikelihoodProblem p = small_problem(12);
  const Eigen::MatrixXd X = test::random_points(12, 2, 13, 0.5);
  const double plain = log_likelihood(p, X);
  p.prior.complexity_weight = 0.7;
  const double det_prior = 0.3 * p.columns * std::log(covariance_matrix(X, p.kernel).determinant());
  EXPECT_NEAR(log_likelihood(p, X), plain + det_prior, 1e-9 * std::abs(plain));
  p.prior = LatentPrior{1.5, 0.4, 0.2, 1.0};
  double repulsion = 0;
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      repulsion += std::log(1.0 - std::exp(-(X.row(i) - X.row(j)).squaredNorm() / 0.16));
  const double expected = plain + p.columns * (1.5 * repulsion - 0.1 * X.squaredNorm());
  EXPECT_NEAR(log_likelihood(p, X), expected, 1e-9 * std::abs(expected));
}

TEST(Likelihood, RejectsInvalidPriors) {
  LikelihoodProblem p = small_problem(14);
  for (const LatentPrior bad : {LatentPrior{0, 0.1, 0, 0.0}, LatentPrior{0, 0.1, 0, 1.5}, LatentPrior{-1, 0.1, 0, 1},
                                LatentPrior{1, 0.0, 0, 1}, LatentPrior{0, 0.1, -1, 1}, LatentPrior{NAN, 0.1, 0, 1}}) {
    p.prior = bad;
    EXPECT_THROW(LikelihoodEvaluator{p}, Error);
  }
}

TEST(Likelihood, ScalingTheDataShiftsByTheAnalyticConstant) {
  const LikelihoodProblem p = small_problem(4);
  LikelihoodProblem scaled = p;
  const double c = 1e6;
  scaled.gram *= c;
  const Eigen::MatrixXd X = test::random_points(12, 3, 5);
  Eigen::MatrixXd G, Gs;
  const double L = log_likelihood(p, X, &G), Ls = log_likelihood(scaled, X, &Gs);
  EXPECT_NEAR(Ls - L, -12.0 * p.columns * std::log(c), 1e-9 * std::abs(L));
  EXPECT_LT((Gs - G).norm(), 1e-9 * G.norm());
}

TEST(Likelihood, EvaluatorNormalisedValueIsIndependentOfColumnsAndScale) {
  LikelihoodProblem p = small_problem(6);
  const Eigen::MatrixXd X = test::random_points(12, 2, 7);
  LikelihoodEvaluator a(p);
  p.columns = 4.37e6;
  p.gram *= 3.0;
  LikelihoodEvaluator b(p);
  EXPECT_NEAR(a.normalized(X), b.normalized(X), 1e-10);
  EXPECT_NEAR(b(X), log_likelihood(p, X), 1e-12 * std::abs(b(X)));
  EXPECT_NEAR(b.to_log_likelihood(b.normalized(X)), reference_likelihood(p, X), 1e-9 * std::abs(b(X)));
}

TEST(Likelihood, RejectsMalformedProblems) {
  const LikelihoodProblem good = small_problem(8);
  const Eigen::MatrixXd X = test::random_points(12, 2, 9);
  LikelihoodProblem p = good;
  p.gram = Eigen::MatrixXd::Zero(12, 12);
  EXPECT_THROW(log_likelihood(p, X), Error);  // all rows equal
  p = good;
  p.gram.conservativeResize(12, 11);
  EXPECT_THROW(log_likelihood(p, X), Error);
  p = good;
  p.gram(0, 0) = -1e3;
  EXPECT_THROW(log_likelihood(p, X), Error);  // not PSD
  p = good;
  p.columns = 0;
  EXPECT_THROW(log_likelihood(p, X), Error);
  EXPECT_THROW(log_likelihood(good, test::random_points(11, 2, 9)), Error);
}

TEST(Likelihood, DuplicatePointsFailOnlyWithoutNugget) {
  LikelihoodProblem p = small_problem(10);
  Eigen::MatrixXd X = test::random_points(12, 2, 11);
  X.row(5) = X.row(2);
  EXPECT_TRUE(std::isfinite(log_likelihood(p, X)));
  p.kernel.nugget = 0;
  try {
    log_likelihood(p, X);
    FAIL() << "expected matlas::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace matlas::gp
