// Gram-space leave-one-out algebra and the PCA baseline against explicit data matrices.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/SVD>

#include "eval/gram_space.h"
#include "eval/pca_baseline.h"

namespace matlas::eval {
namespace {

/// n x D data with a known structure: mean + rank-r scores times orthogonal-ish directions.
Eigen::MatrixXd low_rank_data(int n, int D, int rank, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixXd scores(n, rank), dirs(rank, D);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < rank; ++k) scores(i, k) = g(rng) * (rank - k);
  for (int k = 0; k < rank; ++k)
    for (int j = 0; j < D; ++j) dirs(k, j) = g(rng);
  Eigen::RowVectorXd offset(D);
  for (int j = 0; j < D; ++j) offset(j) = 3.0 + g(rng);
  return (scores * dirs).rowwise() + offset;
}

Eigen::MatrixXd centred_gram(const Eigen::MatrixXd& Z) {
  const Eigen::MatrixXd c = Z.rowwise() - Z.colwise().mean();
  return c * c.transpose();
}

TEST(GramSpace, ResidualMatchesExplicitData) {
  const Eigen::MatrixXd Z = low_rank_data(7, 40, 7, 1);
  const Eigen::MatrixXd G = centred_gram(Z);
  Eigen::VectorXd c(7);
  c << 0.2, 0.5, -0.1, 0.0, 0.3, 0.1, 0.0;  // sums to 1
  const Eigen::RowVectorXd r = c.transpose() * Z;
  EXPECT_NEAR(residual_squared(G, c, 3), (Z.row(3) - r).squaredNorm(), 1e-9);
  const Eigen::MatrixXd d = squared_distances_from_gram(G);
  EXPECT_NEAR(d(1, 4), (Z.row(1) - Z.row(4)).squaredNorm(), 1e-9);
}

TEST(GramSpace, SubsetCentringMatchesRecentredData) {
  const Eigen::MatrixXd Z = low_rank_data(6, 30, 6, 2);
  const Eigen::MatrixXd G = centred_gram(Z);
  const std::vector<int> subset = indices_without(6, 2);
  Eigen::MatrixXd Zs(5, 30);
  for (int k = 0; k < 5; ++k) Zs.row(k) = Z.row(subset[static_cast<std::size_t>(k)]);
  const Eigen::RowVectorXd m = Zs.colwise().mean();
  EXPECT_TRUE(centred_subset_gram(G, subset).isApprox(centred_gram(Zs), 1e-10));
  const Eigen::VectorXd cross = centred_cross_products(G, subset, 2);
  const Eigen::VectorXd expected = (Zs.rowwise() - m) * (Z.row(2) - m).transpose();
  EXPECT_TRUE(cross.isApprox(expected, 1e-10));
  // raw_from_centred: m + sum a_k (z_k - m).
  Eigen::VectorXd a(5);
  a << 0.3, -0.2, 0.4, 0.1, 0.7;
  const Eigen::VectorXd c = raw_from_centred(a, subset, 6);
  EXPECT_NEAR(c.sum(), 1.0, 1e-14);
  EXPECT_EQ(c(2), 0.0);
  const Eigen::RowVectorXd expect_row = m + a.transpose() * (Zs.rowwise() - m);
  EXPECT_TRUE((c.transpose() * Z).isApprox(expect_row, 1e-12));
}

TEST(PcaBaseline, ReconstructsExactlyInsideTheSpan) {
  // Rank-3 variation: with 3 components fitted on the others, a held-out material that lies in
  // the same affine span is reconstructed exactly; with fewer it is not.
  const Eigen::MatrixXd Z = low_rank_data(8, 50, 3, 3);
  const Eigen::MatrixXd G = centred_gram(Z);
  const std::vector<int> subset = indices_without(8, 5);
  const Eigen::VectorXd c3 = pca_reconstruction(G, subset, 5, 3);
  EXPECT_NEAR(c3.sum(), 1.0, 1e-12);
  EXPECT_EQ(c3(5), 0.0);
  EXPECT_LT(residual_squared(G, c3, 5), 1e-9 * G.trace());
  const Eigen::VectorXd c1 = pca_reconstruction(G, subset, 5, 1);
  EXPECT_GT(residual_squared(G, c1, 5), 1e-3 * G.trace() / 8);
}

TEST(PcaBaseline, MatchesExplicitSvdProjection) {
  const Eigen::MatrixXd Z = low_rank_data(9, 60, 9, 4);
  const Eigen::MatrixXd G = centred_gram(Z);
  const int h = 0, q = 2;
  const std::vector<int> subset = indices_without(9, h);
  Eigen::MatrixXd Zs(8, 60);
  for (int k = 0; k < 8; ++k) Zs.row(k) = Z.row(subset[static_cast<std::size_t>(k)]);
  const Eigen::RowVectorXd m = Zs.colwise().mean();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Zs.rowwise() - m, Eigen::ComputeThinV);
  const Eigen::MatrixXd U = svd.matrixV().leftCols(q);  // 60 x q principal directions
  const Eigen::RowVectorXd d = Z.row(h) - m;
  const Eigen::RowVectorXd expected = m + (d * U) * U.transpose();
  const Eigen::VectorXd c = pca_reconstruction(G, subset, h, q);
  EXPECT_TRUE((c.transpose() * Z).isApprox(expected, 1e-9));
  EXPECT_NEAR(residual_squared(G, c, h), (Z.row(h) - expected).squaredNorm(), 1e-8);
}

TEST(PcaBaseline, ZeroComponentsGiveTheMean) {
  const Eigen::MatrixXd Z = low_rank_data(5, 20, 5, 5);
  const std::vector<int> subset = indices_without(5, 1);
  const Eigen::VectorXd c = pca_reconstruction(centred_gram(Z), subset, 1, 0);
  for (int i : subset) EXPECT_NEAR(c(i), 0.25, 1e-15);
}

}  // namespace
}  // namespace matlas::eval
