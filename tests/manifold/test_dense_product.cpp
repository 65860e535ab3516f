// blas_product (manifold/dense_product.h) against Eigen's product for each way it splits the work
// over the workers: bands of result columns, bands of result rows, and chunks of a long inner
// dimension added in a fixed order (the same result for any thread count).
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "manifold/dense_product.h"

namespace matlas {
namespace {

void expect_product(Eigen::Index m, Eigen::Index k, Eigen::Index p) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(m, k), b = Eigen::MatrixXd::Random(k, p);
  const Eigen::MatrixXd expected = a * b;
  const Eigen::MatrixXd c = blas_product(a, b);
  ASSERT_EQ(c.rows(), m);
  ASSERT_EQ(c.cols(), p);
  EXPECT_LT((c - expected).cwiseAbs().maxCoeff(), 1e-12 * static_cast<double>(k)) << m << " x " << k << " x " << p;
}

TEST(BlasProduct, EqualsEigensProductForEverySplit) {
  expect_product(7, 5, 300);         // wide result: bands of columns
  expect_product(300, 5, 7);         // tall result: bands of rows
  expect_product(9, 200000, 6);      // long inner dimension: chunks summed in order
  expect_product(1, 1, 1);
  expect_product(65, 64, 129);       // bands that do not divide the result
}

TEST(BlasProduct, EmptyInnerDimensionGivesZeros) {
  const Eigen::MatrixXd c = blas_product(Eigen::MatrixXd(3, 0), Eigen::MatrixXd(0, 4));
  ASSERT_EQ(c.rows(), 3);
  ASSERT_EQ(c.cols(), 4);
  EXPECT_EQ(c.cwiseAbs().maxCoeff(), 0.0);
}

TEST(BlasProduct, LongInnerDimensionDoesNotDependOnTheWorkers) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(5, 300000), b = Eigen::MatrixXd::Random(300000, 4);
  const Eigen::MatrixXd first = blas_product(a, b);
  for (int r = 0; r < 3; ++r) EXPECT_EQ(blas_product(a, b), first);
}

}  // namespace
}  // namespace matlas
