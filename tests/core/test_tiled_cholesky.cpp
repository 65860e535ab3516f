// core/tiled_cholesky.h: the tiled factorisation and inverse against LAPACK's and Eigen's, at sizes
// of one tile, several and a ragged last one; the first failing leading minor; the same bits on one
// worker as on all of them.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/blas.h"
#include "core/tiled_cholesky.h"
#include "one_worker.h"

namespace matlas {
namespace {

Eigen::MatrixXd spd(int n) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  return a * a.transpose() / n + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

Eigen::MatrixXd lapack_factor(const Eigen::MatrixXd& K) {
  Eigen::MatrixXd L = K;
  int n = static_cast<int>(K.rows()), info = -1;
  blas::openblas().dpotrf("L", &n, L.data(), &n, &info);
  EXPECT_EQ(info, 0);
  return L.triangularView<Eigen::Lower>();
}

TEST(TiledCholesky, IsLapacksFactorAndLeavesTheUpperTriangle) {
  for (const int tile : {16, 128}) {
    for (const int n : {1, 7, 16, 17, 48, 100, 130}) {
      SCOPED_TRACE(testing::Message() << "n " << n << " tile " << tile);
      const Eigen::MatrixXd K = spd(n);
      Eigen::MatrixXd got = K;
      for (Eigen::Index j = 1; j < n; ++j)
        for (Eigen::Index i = 0; i < j; ++i) got(i, j) = 7.0;
      ASSERT_EQ(blas::tiled_cholesky(n, got.data(), n, tile), 0);
      const Eigen::MatrixXd L = got.triangularView<Eigen::Lower>();
      EXPECT_LT((L - lapack_factor(K)).norm(), 1e-12 * L.norm());
      EXPECT_LT((L * L.transpose() - K).norm(), 1e-12 * K.norm());
      for (Eigen::Index j = 1; j < n; ++j)
        for (Eigen::Index i = 0; i < j; ++i) EXPECT_EQ(got(i, j), 7.0);
    }
  }
}

TEST(TiledCholesky, ReportsTheFirstLeadingMinorThatIsNotPositiveDefinite) {
  const int n = 70;
  for (const int bad : {1, 16, 17, 40, 70}) {
    SCOPED_TRACE(bad);
    Eigen::MatrixXd K = spd(n);
    // A negative diagonal entry at bad - 1: the leading minor of order `bad` has a negative Schur
    // complement, those before it are untouched.
    K(bad - 1, bad - 1) = -1.0;
    Eigen::MatrixXd got = K;
    EXPECT_EQ(blas::tiled_cholesky(n, got.data(), n, 16), bad);
  }
}

TEST(TiledInverseFromCholesky, IsTheInverse) {
  for (const int tile : {16, 128}) {
    for (const int n : {1, 7, 16, 17, 48, 100, 130}) {
      SCOPED_TRACE(testing::Message() << "n " << n << " tile " << tile);
      const Eigen::MatrixXd K = spd(n);
      const Eigen::MatrixXd L = lapack_factor(K);
      Eigen::MatrixXd work(n, n), got = Eigen::MatrixXd::Constant(n, n, 7.0);
      ASSERT_EQ(blas::tiled_inverse_from_cholesky(n, L.data(), n, work.data(), got.data(), n, tile), 0);
      const Eigen::MatrixXd full = got.selfadjointView<Eigen::Lower>();
      const Eigen::MatrixXd want = K.inverse();
      EXPECT_LT((full - want).norm(), 1e-10 * want.norm());
      EXPECT_LT((full * K - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-9 * n);
    }
  }
}

TEST(TiledInverseFromCholesky, ReportsAZeroPivot) {
  const int n = 40;
  Eigen::MatrixXd L = lapack_factor(spd(n));
  L(22, 22) = 0.0;
  Eigen::MatrixXd work(n, n), got(n, n);
  EXPECT_EQ(blas::tiled_inverse_from_cholesky(n, L.data(), n, work.data(), got.data(), n, 16), 23);
}

TEST(TiledCholesky, OneWorkerGivesTheSameBitsAsAll) {
  const int n = 300;
  const Eigen::MatrixXd K = spd(n);
  const auto both = [&] {
    Eigen::MatrixXd L = K, work(n, n), inverse(n, n);
    EXPECT_EQ(blas::tiled_cholesky(n, L.data(), n, 64), 0);
    EXPECT_EQ(blas::tiled_inverse_from_cholesky(n, L.data(), n, work.data(), inverse.data(), n, 64), 0);
    return std::pair<Eigen::MatrixXd, Eigen::MatrixXd>(L.triangularView<Eigen::Lower>(),
                                                      inverse.triangularView<Eigen::Lower>());
  };
  const auto all = both(), one = test::on_one_worker(both);
  EXPECT_TRUE(one.first == all.first);
  EXPECT_TRUE(one.second == all.second);
}

}  // namespace
}  // namespace matlas
