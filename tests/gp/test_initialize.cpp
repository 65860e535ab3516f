#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.h"
#include "gp/initialize.h"
#include "gp_test_data.h"

namespace matlas::gp {
namespace {

LikelihoodProblem problem() {
  LikelihoodProblem p = test::problem_for(test::random_low_rank_data(20, 60, 4, 31));
  p.columns = 4.37e6;
  return p;
}

TEST(PcaInitialization, ColumnsArePrincipalAxes) {
  const LikelihoodProblem p = problem();
  const Eigen::MatrixXd X = pca_initialization(p, 2);
  ASSERT_EQ(X.rows(), 20);
  ASSERT_EQ(X.cols(), 2);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(p.gram);
  for (int k = 0; k < 2; ++k) {
    const Eigen::VectorXd u = eig.eigenvectors().col(19 - k);
    EXPECT_NEAR(std::abs(X.col(k).normalized().dot(u)), 1.0, 1e-9) << "axis " << k;
  }
  // Columns scaled like PCA scores: norms in the ratio sqrt(lambda_1 / lambda_2).
  EXPECT_NEAR(X.col(0).norm() / X.col(1).norm(), std::sqrt(eig.eigenvalues()[19] / eig.eigenvalues()[18]), 1e-9);
  EXPECT_NEAR(X.col(0).mean(), 0.0, 1e-9);  // centred data: scores have zero mean
}

TEST(PcaInitialization, ScaleIsALocalMaximumOfTheLikelihood) {
  const LikelihoodProblem p = problem();
  const Eigen::MatrixXd X = pca_initialization(p, 3);
  const double L = log_likelihood(p, X);
  EXPECT_LE(log_likelihood(p, 1.02 * X), L);
  EXPECT_LE(log_likelihood(p, 0.98 * X), L);
  // And clearly better than badly scaled starts.
  EXPECT_LT(log_likelihood(p, 10.0 * X), L);
  EXPECT_LT(log_likelihood(p, 0.1 * X), L);
}

TEST(PcaInitialization, DeterministicAndIndependentOfDataScale) {
  const LikelihoodProblem p = problem();
  LikelihoodProblem scaled = p;
  scaled.gram *= 1e6;
  const Eigen::MatrixXd a = pca_initialization(p, 2), b = pca_initialization(p, 2), c = pca_initialization(scaled, 2);
  EXPECT_EQ(a, b);
  EXPECT_LT((a - c).cwiseAbs().maxCoeff(), 1e-6 * a.cwiseAbs().maxCoeff());
}

TEST(PcaInitialization, RejectsBadDimension) {
  EXPECT_THROW(pca_initialization(problem(), 0), Error);
}

}  // namespace
}  // namespace matlas::gp
