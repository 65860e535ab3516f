#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "gp/kernel.h"
#include "gp_test_data.h"

namespace matlas::gp {
namespace {

TEST(Kernel, SquaredExponentialValue) {
  const Kernel k{2.0, 1e-3};
  Eigen::Vector2d a(0.5, -1.0), b(1.5, 1.0);
  // |a-b|^2 = 1 + 4 = 5, l^2 = 4.
  EXPECT_NEAR(k(a, b), std::exp(-5.0 / 4.0), 1e-15);
  EXPECT_EQ(k(a, a), 1.0);
}

TEST(Kernel, CovarianceMatrixIsSymmetricWithNuggetOnDiagonal) {
  const Eigen::MatrixXd X = test::random_points(9, 3, 7);
  const Kernel k{0.8, 1e-2};
  const Eigen::MatrixXd K = covariance_matrix(X, k);
  ASSERT_EQ(K.rows(), 9);
  EXPECT_EQ((K - K.transpose()).cwiseAbs().maxCoeff(), 0.0);
  for (int i = 0; i < 9; ++i) {
    EXPECT_NEAR(K(i, i), 1.0 + k.nugget, 1e-15);
    for (int j = 0; j < 9; ++j)
      if (i != j) {
        EXPECT_NEAR(K(i, j), k(X.row(i).transpose(), X.row(j).transpose()), 1e-14);
      }
  }
}

TEST(Kernel, CrossCovarianceAddsNuggetOnlyAtExactDataPoints) {
  const Eigen::MatrixXd X = test::random_points(6, 2, 3);
  const Kernel k{1.0, 0.25};
  const Eigen::MatrixXd K = covariance_matrix(X, k);
  const Eigen::VectorXd at_data = cross_covariance(X, X.row(4).transpose(), k);
  EXPECT_LT((at_data - K.col(4)).cwiseAbs().maxCoeff(), 1e-14);
  Eigen::VectorXd nearby_point = X.row(4).transpose();
  nearby_point[0] += 1e-12;
  const Eigen::VectorXd nearby = cross_covariance(X, nearby_point, k);
  EXPECT_NEAR(nearby[4], 1.0, 1e-15);  // no nugget: it is not the same point
  EXPECT_THROW(cross_covariance(X, Eigen::Vector3d(0, 0, 0), k), Error);
}

TEST(Kernel, BatchCrossCovarianceMatchesSingle) {
  const Eigen::MatrixXd X = test::random_points(5, 2, 11);
  const Eigen::MatrixXd P = test::random_points(4, 2, 12);
  const Kernel k{1.3, 1e-4};
  const Eigen::MatrixXd B = cross_covariance_batch(X, P, k);
  for (int j = 0; j < 4; ++j) EXPECT_EQ(B.col(j), cross_covariance(X, P.row(j).transpose(), k));
}

TEST(Kernel, ValidateRejectsBadParameters) {
  EXPECT_THROW(validate(Kernel{0.0, 1e-4}), Error);
  EXPECT_THROW(validate(Kernel{1.0, -1.0}), Error);
  EXPECT_THROW(validate(Kernel{std::nan(""), 1e-4}), Error);
  EXPECT_NO_THROW(validate(Kernel{1.0, 0.0}));
}

}  // namespace
}  // namespace matlas::gp
