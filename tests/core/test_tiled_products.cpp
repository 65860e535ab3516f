// core/tiled_products.h: the tiled products against Eigen's, at one block, several and a ragged last
// one; the strict upper triangle untouched; the same bits on one worker as on all of them.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "core/tiled_products.h"
#include "one_worker.h"

namespace matlas {
namespace {

TEST(TiledProduct, IsTheProduct) {
  for (const int block : {8, 128}) {
    for (const auto& [m, n, k] : {std::tuple{1, 1, 1}, {30, 7, 12}, {40, 33, 5}, {17, 100, 64}}) {
      SCOPED_TRACE(testing::Message() << m << " x " << n << " x " << k << " block " << block);
      const Eigen::MatrixXd A = Eigen::MatrixXd::Random(m, k), B = Eigen::MatrixXd::Random(k, n);
      Eigen::MatrixXd C = Eigen::MatrixXd::Constant(m, n, 7.0);
      blas::tiled_product(m, n, k, 0.5, A.data(), m, B.data(), k, C.data(), m, block);
      const Eigen::MatrixXd want = 0.5 * A * B;
      EXPECT_LT((C - want).norm(), 1e-13 * want.norm());
    }
  }
}

TEST(TiledLowerGram, IsTheLowerTriangleOfAAtPlusBetaC) {
  for (const int tile : {8, 256}) {
    for (const auto& [n, k] : {std::pair{1, 1}, {9, 3}, {40, 17}, {100, 64}}) {
      SCOPED_TRACE(testing::Message() << n << " x " << k << " tile " << tile);
      const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, k);
      for (const double beta : {0.0, 0.5}) {
        Eigen::MatrixXd C = Eigen::MatrixXd::Constant(n, n, 7.0);
        blas::tiled_lower_gram(n, k, 2.0, A.data(), n, beta, C.data(), n, tile);
        const Eigen::MatrixXd want = (2.0 * A * A.transpose()).array() + beta * 7.0;
        for (Eigen::Index j = 0; j < n; ++j)
          for (Eigen::Index i = 0; i < n; ++i) {
            if (i >= j)
              EXPECT_NEAR(C(i, j), want(i, j), 1e-13 * want.norm()) << "beta " << beta;
            else
              EXPECT_EQ(C(i, j), 7.0);
          }
      }
    }
  }
}

TEST(TiledProducts, OneWorkerGivesTheSameBitsAsAll) {
  const int n = 300, k = 200;
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n), B = Eigen::MatrixXd::Random(n, k);
  const auto both = [&] {
    Eigen::MatrixXd P(n, k), G = Eigen::MatrixXd::Zero(n, n);
    blas::tiled_product(n, k, n, 1.0, A.data(), n, B.data(), n, P.data(), n, 32);
    blas::tiled_lower_gram(n, k, 1.0, P.data(), n, 0.0, G.data(), n, 64);
    return std::pair<Eigen::MatrixXd, Eigen::MatrixXd>(P, G);
  };
  const auto all = both(), one = test::on_one_worker(both);
  EXPECT_TRUE(one.first == all.first);
  EXPECT_TRUE(one.second == all.second);
}

}  // namespace
}  // namespace matlas
