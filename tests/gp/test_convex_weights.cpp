#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "core/combination.h"
#include "core/error.h"
#include "gp/convex_weights.h"
#include "gp/posterior.h"
#include "gp_test_data.h"

namespace matlas::gp {
namespace {

/// Random affine coefficients (sum 1) with some large negative entries, like GP weights between
/// clustered points.
Eigen::VectorXd random_affine(int n, std::uint64_t seed, double spread = 1.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, spread);
  Eigen::VectorXd g(n);
  for (int i = 0; i < n; ++i) g[i] = normal(rng);
  g.array() += (1.0 - g.sum()) / n;
  return g;
}

/// Independent optimality check: the KKT conditions of min (c-g)^T A (c-g) over the simplex,
/// sufficient for a convex problem. r = A (c - g); every r_i with c_i > 0 equals nu and every
/// r_j with c_j = 0 is >= nu.
void expect_kkt(const Eigen::MatrixXd& A, const Eigen::VectorXd& g, const Eigen::VectorXd& c) {
  ASSERT_GE(c.minCoeff(), 0.0);
  ASSERT_NEAR(c.sum(), 1.0, 1e-12);
  const Eigen::VectorXd r = A * (c - g);
  double nu = 0;
  int active = 0;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    if (c[i] > 1e-12) {
      nu += r[i];
      ++active;
    }
  ASSERT_GT(active, 0);
  nu /= active;
  const double tol = 1e-8 * (1.0 + r.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    if (c[i] > 1e-12)
      EXPECT_NEAR(r[i], nu, tol) << "free coefficient " << i;
    else
      EXPECT_GE(r[i], nu - tol) << "bound coefficient " << i;
  }
}

/// Reference: Euclidean projection onto the simplex by sorting (Held, Wolfe & Crowder 1974).
Eigen::VectorXd euclidean_simplex_projection(const Eigen::VectorXd& g) {
  std::vector<double> u(g.data(), g.data() + g.size());
  std::sort(u.begin(), u.end(), std::greater<>());
  double sum = 0, theta = 0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    sum += u[k];
    const double t = (sum - 1.0) / static_cast<double>(k + 1);
    if (u[k] - t > 0) theta = t;
  }
  return (g.array() - theta).cwiseMax(0.0);
}

TEST(ConvexProjection, ResultIsConvexAndSatisfiesTheOptimalityConditions) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const int n = 5 + static_cast<int>(seed % 7) * 13;
    const Eigen::MatrixXd S = test::centred_gram(test::random_low_rank_data(n, 60, 4, seed));
    const ConvexProjection p(S, 1e-3);
    const Eigen::VectorXd g = random_affine(n, seed + 100, 0.5 + 0.1 * static_cast<double>(seed));
    const Eigen::VectorXd c = p.project(g);
    expect_kkt(p.metric(), g, c);
  }
}

TEST(ConvexProjection, NearDuplicateInputsStillSolveExactly) {
  // Clusters of near-identical materials (the case that breaks GP weights): rank-deficient S.
  const int n = 30;
  Eigen::MatrixXd Z = test::random_low_rank_data(n, 40, 3, 7, 1e-6);
  for (int i = 10; i < 20; ++i) Z.row(i) = Z.row(0) + 1e-9 * Z.row(i);
  const ConvexProjection p(test::centred_gram(Z), 1e-6);
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    const Eigen::VectorXd g = random_affine(n, seed, 3.0);
    expect_kkt(p.metric(), g, p.project(g));
  }
}

TEST(ConvexProjection, EuclideanMetricMatchesTheSortingProjection) {
  // S = 0 (all inputs identical): A is the ridge times the identity.
  const int n = 17;
  const ConvexProjection p(Eigen::MatrixXd::Zero(n, n), 0.5);
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const Eigen::VectorXd g = random_affine(n, seed, 2.0);
    EXPECT_LT((p.project(g) - euclidean_simplex_projection(g)).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(ConvexProjection, ConvexCoefficientsAndUnitVectorsAreUnchanged) {
  const int n = 12;
  const ConvexProjection p(test::centred_gram(test::random_low_rank_data(n, 20, 3, 3)));
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(n, i);
    EXPECT_EQ(p.project(e), e);
  }
  Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(n, 0.0, 1.0);
  g /= g.sum();
  EXPECT_LT((p.project(g) - g).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ConvexProjection, IsNonExpansiveInTheMetric) {
  // |c(g) - c(h)|_A <= |g - h|_A for any g, h: continuity with an explicit constant.
  const int n = 25;
  const ConvexProjection p(test::centred_gram(test::random_low_rank_data(n, 50, 5, 11)), 1e-3);
  const Eigen::MatrixXd& A = p.metric();
  auto norm = [&](const Eigen::VectorXd& v) { return std::sqrt(v.dot(A * v)); };
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    const Eigen::VectorXd g = random_affine(n, 2 * seed, 1.0);
    const Eigen::VectorXd h = g + 0.05 * (random_affine(n, 2 * seed + 1, 1.0) - g);
    EXPECT_LE(norm(p.project(g) - p.project(h)), norm(g - h) * (1 + 1e-9) + 1e-12);
  }
}

TEST(ConvexProjection, GpWeightsAlongADensePathAreConvexContinuousAndExactAtTheData) {
  // A GP over clustered latent points (where its weights swing far below 0), walked densely.
  const int n = 20;
  Eigen::MatrixXd X = test::random_points(n, 2, 5, 2.0);
  for (int i = 1; i < 6; ++i) X.row(i) = X.row(0) + 0.05 * X.row(i);  // a tight cluster
  const GpPosterior gp(X, Kernel{1.0, 1e-4});
  const ConvexProjection p(test::centred_gram(test::random_low_rank_data(n, 30, 4, 9)));
  const Eigen::MatrixXd& A = p.metric();
  auto norm = [&](const Eigen::VectorXd& v) { return std::sqrt(v.dot(A * v)); };
  const Eigen::Vector2d a = X.row(0).transpose(), b = X.row(7).transpose();
  auto path = [&](double t) { return Eigen::Vector2d(a + (b - a) * t + Eigen::Vector2d(0, 0.3) * std::sin(3.14159 * t)); };
  // Largest jump of the convex weights between neighbouring points, for a path of `steps` steps;
  // each jump is bounded by the GP's own (non-expansive projection).
  double most_negative_gp = 0;
  auto largest_jump = [&](int steps) {
    Eigen::VectorXd previous_c, previous_g;
    double largest = 0;
    for (int s = 0; s <= steps; ++s) {
      const Eigen::VectorXd g = Combination(gp.weights(path(static_cast<double>(s) / steps))).affine();
      most_negative_gp = std::min(most_negative_gp, g.minCoeff());
      const Eigen::VectorXd c = p.project(g);
      EXPECT_GE(c.minCoeff(), 0.0);
      EXPECT_NEAR(c.sum(), 1.0, 1e-12);
      if (s > 0) {
        EXPECT_LE(norm(c - previous_c), norm(g - previous_g) * (1 + 1e-9) + 1e-13);
        largest = std::max(largest, (c - previous_c).cwiseAbs().maxCoeff());
      }
      previous_c = c;
      previous_g = g;
    }
    return largest;
  };
  const double coarse = largest_jump(2000), fine = largest_jump(20000);
  EXPECT_LT(most_negative_gp, -0.05) << "the path should cross regions where the GP weights are negative";
  // Continuous: ten times finer steps, about ten times smaller jumps (a discontinuity would stay).
  EXPECT_LT(fine, 0.2 * coarse);
  EXPECT_LT(fine, 0.05);
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd c = p.from_centred(gp.weights(X.row(i).transpose()));
    EXPECT_LT((c - Eigen::VectorXd::Unit(n, i)).cwiseAbs().maxCoeff(), 1e-9) << "material " << i;
  }
}

/// A GP over clustered 2D points whose points sit on cell centres of a cols x rows grid over
/// [-4, 4]^2 (far beyond the data at the edges), and the GP weights of every cell, row-major with
/// row 0 at the top, as a map's grid has them.
struct GridCase {
  int cols = 48, rows = 40;
  Eigen::MatrixXd X;  // n x 2
  Eigen::MatrixXd W;  // n x (cols * rows): GP weights of the centred data
  Eigen::VectorXd variance;  // the GP's predictive variance per cell
  std::vector<Eigen::Index> data_cells;
};
GridCase grid_case(int n, std::uint64_t seed) {
  GridCase t;
  const double lo = -4, hi = 4;
  auto centre = [&](int c, int r) {
    return Eigen::Vector2d(lo + (c + 0.5) / t.cols * (hi - lo), hi - (r + 0.5) / t.rows * (hi - lo));
  };
  // Points in the middle half of the grid, a third of them in tight clusters (nearby cells).
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> col(t.cols / 4, 3 * t.cols / 4), row(t.rows / 4, 3 * t.rows / 4);
  std::uniform_int_distribution<int> step(-1, 1);
  std::set<std::pair<int, int>> used;
  t.X.resize(n, 2);
  for (int i = 0; i < n; ++i) {
    std::pair<int, int> cell;
    do {
      if (i % 3 == 2 && i > 0) {
        const std::pair<int, int> prev = *std::prev(used.end());
        cell = {std::clamp(prev.first + step(rng), 0, t.cols - 1), std::clamp(prev.second + step(rng), 0, t.rows - 1)};
      } else {
        cell = {col(rng), row(rng)};
      }
    } while (used.count(cell));
    used.insert(cell);
    t.X.row(i) = centre(cell.first, cell.second).transpose();
    t.data_cells.push_back(static_cast<Eigen::Index>(cell.second) * t.cols + cell.first);
  }
  const GpPosterior gp(t.X, Kernel{1.0, 1e-4});
  Eigen::MatrixXd points(t.cols * t.rows, 2);
  for (int r = 0; r < t.rows; ++r)
    for (int c = 0; c < t.cols; ++c) points.row(static_cast<Eigen::Index>(r) * t.cols + c) = centre(c, r).transpose();
  GpPosterior::Batch b = gp.predict_batch(points);
  t.W = std::move(b.weights);
  t.variance = std::move(b.variance);
  return t;
}

TEST(ConvexProjection, BatchOverAGridEqualsThePerPointSolveEverywhere) {
  for (std::uint64_t seed : {3u, 8u}) {
    const int n = 60;
    const GridCase t = grid_case(n, seed);
    const ConvexProjection p(test::centred_gram(test::random_low_rank_data(n, 80, 6, seed + 1)));
    const Eigen::Index m = t.W.cols();
    Eigen::MatrixXd G = t.W;
    for (Eigen::Index j = 0; j < m; ++j) G.col(j) = Combination(t.W.col(j)).affine();
    // The reference: project() at every cell, each solved on its own from the cold start.
    Eigen::MatrixXd expected(n, m);
    int projected = 0;
    for (Eigen::Index j = 0; j < m; ++j) {
      expected.col(j) = p.project(G.col(j));
      projected += G.col(j).minCoeff() < 0;
    }
    // The grid must exercise the solver: most cells need it (far cells and between clusters).
    ASSERT_GT(projected, m / 2);
    // Equal to the per-point solve: to rounding where g is clearly not convex; at the data points,
    // where g is a unit vector plus the GP's rounding (entries of 1e-11 either side of 0), the two
    // starts may end on supports that differ by entries of that size, which the multiplier test
    // (1e-11 relative to A g) cannot tell apart: there they agree to a few 1e-11.
    auto expect_equal = [&](const Eigen::MatrixXd& batch, Eigen::Index run) {
      double worst = 0, worst_clear = 0;
      for (Eigen::Index j = 0; j < m; ++j) {
        const double d = (batch.col(j) - expected.col(j)).cwiseAbs().maxCoeff();
        worst = std::max(worst, d);
        if (G.col(j).minCoeff() < -1e-9) worst_clear = std::max(worst_clear, d);
      }
      EXPECT_LT(worst_clear, 1e-12) << "run " << run;
      EXPECT_LT(worst, 1e-10) << "run " << run;
    };
    for (Eigen::Index run : {Eigen::Index{t.cols}, Eigen::Index{1}, Eigen::Index{7}, Eigen::Index{0}}) {
      Eigen::MatrixXd batch = G;
      p.project_batch(batch, run);
      expect_equal(batch, run);
      Eigen::MatrixXd centred = t.W;
      p.from_centred_batch(centred, run);
      expect_equal(centred, run);
    }
    // At the data points the weights are the unit vectors, exactly as the per-point solve.
    Eigen::MatrixXd batch = G;
    p.project_batch(batch, t.cols);
    for (int i = 0; i < n; ++i) {
      const Eigen::Index cell = t.data_cells[static_cast<std::size_t>(i)];
      EXPECT_LT((batch.col(cell) - Eigen::VectorXd::Unit(n, i)).cwiseAbs().maxCoeff(), 1e-9) << "material " << i;
    }
    // The grid reaches far from the data (the corners: predictive variance near its prior 1).
    EXPECT_GT(t.variance[0], 0.9);
    EXPECT_GT(t.variance[m - 1], 0.9);
    // Any order: the cells shuffled, solved one after another.
    std::vector<Eigen::Index> order(static_cast<std::size_t>(m));
    std::iota(order.begin(), order.end(), Eigen::Index{0});
    std::shuffle(order.begin(), order.end(), std::mt19937_64(seed));
    Eigen::MatrixXd shuffled(n, m);
    for (Eigen::Index j = 0; j < m; ++j) shuffled.col(j) = G.col(order[static_cast<std::size_t>(j)]);
    p.project_batch(shuffled, 0);
    Eigen::MatrixXd unshuffled(n, m);
    for (Eigen::Index j = 0; j < m; ++j) unshuffled.col(order[static_cast<std::size_t>(j)]) = shuffled.col(j);
    expect_equal(unshuffled, -1);
  }
}

TEST(ConvexProjection, AWarmStartGivesTheColdSolvesWeightsBitForBit) {
  // A sequence of points (a walk of small steps, then a jump across the map), each solved from
  // the one before (WarmStart, as an optimiser's evaluations and the server's drag steps are):
  // every solution satisfies the optimality conditions and, settled on its support, has the cold
  // solve's bits (the server's weights must not depend on the points asked before).
  const int n = 40;
  const Eigen::MatrixXd X = test::random_points(n, 2, 11, 2.0);
  const GpPosterior gp(X, Kernel{1.0, 1e-4});
  const ConvexProjection p(test::centred_gram(test::random_low_rank_data(n, 60, 5, 3)));
  ConvexProjection::WarmStart warm;
  int needing_the_qp = 0;
  for (int s = 0; s <= 40; ++s) {
    const Eigen::Vector2d x = s < 40 ? Eigen::Vector2d(-1.0 + 0.02 * s, 0.3 - 0.01 * s) : Eigen::Vector2d(2.5, -2.0);
    const Eigen::VectorXd w = gp.weights(x);
    const Eigen::VectorXd g = Combination(w).affine();
    needing_the_qp += g.minCoeff() < 0;
    const Eigen::VectorXd warm_c = p.from_centred(w, warm), cold_c = p.from_centred(w);
    expect_kkt(p.metric(), g, warm_c);
    EXPECT_TRUE(warm_c == cold_c) << "step " << s << ": differs by " << (warm_c - cold_c).cwiseAbs().maxCoeff();
  }
  EXPECT_GT(needing_the_qp, 30);  // the walk exercises the active-set method, not the convex shortcut
}

TEST(ConvexProjection, BatchRejectsMalformedColumns) {
  const ConvexProjection p(Eigen::MatrixXd::Identity(3, 3));
  Eigen::MatrixXd G(3, 2);
  G << 0.2, 0.5, 0.3, 0.5, 0.5, 0.5;  // second column sums to 1.5
  EXPECT_THROW(p.project_batch(G, 0), Error);
  Eigen::MatrixXd wrong(2, 1);
  wrong << 0.5, 0.5;
  EXPECT_THROW(p.project_batch(wrong, 0), Error);
}

TEST(ConvexProjection, RejectsMalformedInput) {
  const ConvexProjection p(Eigen::MatrixXd::Identity(3, 3));
  EXPECT_THROW((void)p.project(Eigen::Vector3d(0.5, 0.5, 0.5)), Error);  // sum 1.5
  EXPECT_THROW((void)p.project(Eigen::Vector2d(0.5, 0.5)), Error);
  EXPECT_THROW((void)p.project(Eigen::Vector3d(NAN, 0.5, 0.5)), Error);
  EXPECT_THROW(ConvexProjection(Eigen::MatrixXd::Identity(3, 3), 0.0), Error);
  EXPECT_THROW(ConvexProjection(Eigen::MatrixXd::Identity(3, 2)), Error);
}

}  // namespace
}  // namespace matlas::gp
