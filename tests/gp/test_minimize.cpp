#include "gp/minimize.h"

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
  const Eigen::VectorXd x = minimize_nelder_mead(f, Eigen::VectorXd::Zero(2), MinimizeOptions::nelder_mead(0.5, 2000));
  EXPECT_NEAR(x(0), expected(0), 1e-4);
  EXPECT_NEAR(x(1), expected(1), 1e-4);
}

TEST(NelderMead, StopsAtTheEvaluationBudget) {
  int calls = 0;
  auto f = [&](const Eigen::VectorXd& x) {
    ++calls;
    return std::abs(x(0) - 3.0) + std::abs(x(1) + 1.0) + std::abs(x(2));
  };
  const Eigen::VectorXd x = minimize_nelder_mead(f, Eigen::VectorXd::Zero(3), MinimizeOptions::nelder_mead(1.0, 40));
  EXPECT_LE(calls, 40 + 4);  // a shrink step may finish past the budget by d evaluations
  EXPECT_LT(f(x), f(Eigen::VectorXd::Zero(3)));  // and it still improved on the start
}

double rosenbrock(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
  const double a = 1.0 - x(0), b = x(1) - x(0) * x(0);
  grad.resize(2);
  grad << -2.0 * a - 400.0 * x(0) * b, 200.0 * b;
  return a * a + 100.0 * b * b;
}

TEST(Lbfgs, FindsTheMinimumOfASmoothConvexFunction) {
  // A quadratic valley with a quartic term: the gradient vanishes at the one minimum.
  auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    grad.resize(2);
    grad << 2 * (x(0) - 1) + 0.5 * x(1) + 0.4 * std::pow(x(0), 3), 20 * (x(1) + 2) + 0.5 * x(0);
    return (x(0) - 1) * (x(0) - 1) + 10 * (x(1) + 2) * (x(1) + 2) + 0.5 * x(0) * x(1) + 0.1 * std::pow(x(0), 4);
  };
  Eigen::VectorXd x(2);
  x << -3.0, 4.0;
  const std::optional<double> value = minimize_lbfgs(f, x, MinimizeOptions{});
  ASSERT_TRUE(value.has_value());
  Eigen::VectorXd grad;
  EXPECT_DOUBLE_EQ(f(x, grad), *value);
  EXPECT_LT(grad.norm(), 1e-7);
}

TEST(Lbfgs, StopsAtTheIterationLimit) {
  int calls = 0;
  auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    ++calls;
    return rosenbrock(x, grad);
  };
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  MinimizeOptions o;
  o.max_iterations = 3;
  const std::optional<double> value = minimize_lbfgs(f, x, o);
  ASSERT_TRUE(value.has_value());
  EXPECT_GT((x - Eigen::Vector2d(1, 1)).norm(), 1e-3);  // not there yet
  EXPECT_LT(*value, 24.2);                              // but below f(x0) = 24.2
  EXPECT_LE(calls, 3 * (o.max_line_search + 1) + 1);
}

TEST(Lbfgs, ReportsAFailedLineSearchInsteadOfThrowing) {
  // No descent possible along a gradient that lies: the line search fails.
  auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    grad = -Eigen::VectorXd::Ones(x.size());
    return x.sum();
  };
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  EXPECT_FALSE(minimize_lbfgs(f, x, MinimizeOptions{}).has_value());
}

}  // namespace
}  // namespace matlas::gp
