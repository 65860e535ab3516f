// blas_product (manifold/dense_product.h) against Eigen's product for each way it splits the work
// over the workers: bands of result columns, bands of result rows, and chunks of a long inner
// dimension added in a fixed order (the same result whichever worker computes which chunk).
#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/Core>

#include "core/blas.h"
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

TEST(BlasProduct, LongInnerDimensionAddsItsChunksInOrder) {
  // Chunks of 2^16 inner columns, each one dgemm, added first to last: the result is exactly that
  // sum whatever the order in which the workers computed the chunks.
  const Eigen::Index k = 300000, chunk = 1 << 16;
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(5, k), b = Eigen::MatrixXd::Random(k, 4);
  Eigen::MatrixXd expected;
  for (Eigen::Index first = 0; first < k; first += chunk) {
    const Eigen::Index count = std::min(chunk, k - first);
    Eigen::MatrixXd part(5, 4);
    blas::openblas().dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, 5, 4, static_cast<int>(count), 1.0,
                           a.data() + first * 5, 5, b.data() + first, static_cast<int>(k), 0.0, part.data(), 5);
    if (first == 0) expected = part;
    else expected += part;
  }
  for (int r = 0; r < 3; ++r) EXPECT_EQ(blas_product(a, b), expected);
}

}  // namespace
}  // namespace matlas
