// core/symmetric_eigen.h: LAPACK's decomposition against Eigen's solver and the definition.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/symmetric_eigen.h"

namespace matlas {
namespace {

TEST(SymmetricEigen, ReconstructsTheMatrixWithOrthonormalVectorsAndAscendingValues) {
  for (const int n : {1, 7, 150}) {
    SCOPED_TRACE(n);
    const Eigen::MatrixXd y = Eigen::MatrixXd::Random(n, n + 3);
    const Eigen::MatrixXd a = y * y.transpose() - 0.5 * Eigen::MatrixXd::Identity(n, n);  // some negative values
    const SymmetricEigen e = symmetric_eigen(a);
    ASSERT_EQ(e.values.size(), n);
    ASSERT_EQ(e.vectors.rows(), n);
    ASSERT_EQ(e.vectors.cols(), n);
    EXPECT_TRUE(std::is_sorted(e.values.data(), e.values.data() + n));
    EXPECT_LT((e.vectors * e.values.asDiagonal() * e.vectors.transpose() - a).norm(), 1e-12 * a.norm());
    EXPECT_LT((e.vectors.transpose() * e.vectors - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-12 * n);
    const Eigen::VectorXd want = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a).eigenvalues();
    EXPECT_LT((e.values - want).cwiseAbs().maxCoeff(), 1e-12 * want.cwiseAbs().maxCoeff());
  }
}

TEST(SymmetricEigen, ReadsTheLowerTriangleOnly) {
  Eigen::MatrixXd a(2, 2);
  a << 2, 99, 1, 2;  // as [[2, 1], [1, 2]]: eigenvalues 1 and 3
  const SymmetricEigen e = symmetric_eigen(a);
  EXPECT_NEAR(e.values[0], 1.0, 1e-14);
  EXPECT_NEAR(e.values[1], 3.0, 1e-14);
}

TEST(SymmetricEigen, RefusesWhatIsNotASymmetricMatrix) {
  EXPECT_THROW(symmetric_eigen(Eigen::MatrixXd::Zero(2, 3)), Error);
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(3, 3);
  a(2, 1) = std::nan("");
  EXPECT_THROW(symmetric_eigen(a), Error);
  EXPECT_EQ(symmetric_eigen(Eigen::MatrixXd(0, 0)).values.size(), 0);
}

}  // namespace
}  // namespace matlas
