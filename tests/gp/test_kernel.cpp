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

TEST(Kernel, ValidateRejectsBadParameters) {
  EXPECT_THROW(validate(Kernel{0.0, 1e-4}), Error);
  EXPECT_THROW(validate(Kernel{1.0, -1.0}), Error);
  EXPECT_THROW(validate(Kernel{std::nan(""), 1e-4}), Error);
  EXPECT_NO_THROW(validate(Kernel{1.0, 0.0}));
}

}  // namespace
}  // namespace matlas::gp
