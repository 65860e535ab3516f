#include "gp/nelder_mead.h"

#include <cmath>

#include <Eigen/LU>
#include <gtest/gtest.h>

namespace matlas::gp {
namespace {

TEST(NelderMead, FindsTheMinimumOfAQuadratic) {
  auto f = [](const Eigen::VectorXd& x) {
    return (x(0) - 1.0) * (x(0) - 1.0) + 10.0 * (x(1) + 2.0) * (x(1) + 2.0) + x(0) * x(1) * 0.5;
  };
  // Minimum: grad = 0 -> 2(x0-1) + 0.5 x1 = 0, 20(x1+2) + 0.5 x0 = 0.
  Eigen::Matrix2d A;
  A << 2, 0.5, 0.5, 20;
  const Eigen::Vector2d expected = A.inverse() * (Eigen::Vector2d(2, -40));
  const Eigen::VectorXd x = nelder_mead(f, Eigen::VectorXd::Zero(2), 0.5, 2000);
  EXPECT_NEAR(x(0), expected(0), 1e-4);
  EXPECT_NEAR(x(1), expected(1), 1e-4);
}

TEST(NelderMead, StopsAtTheEvaluationBudget) {
  int calls = 0;
  auto f = [&](const Eigen::VectorXd& x) {
    ++calls;
    return std::abs(x(0) - 3.0) + std::abs(x(1) + 1.0) + std::abs(x(2));
  };
  const Eigen::VectorXd x = nelder_mead(f, Eigen::VectorXd::Zero(3), 1.0, 40);
  EXPECT_LE(calls, 40 + 4);  // a shrink step may finish past the budget by d evaluations
  EXPECT_LT(f(x), f(Eigen::VectorXd::Zero(3)));  // and it still improved on the start
}

}  // namespace
}  // namespace matlas::gp
