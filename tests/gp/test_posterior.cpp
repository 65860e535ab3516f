#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.h"
#include "gp/posterior.h"
#include "gp_test_data.h"

namespace matlas::gp {
namespace {

GpPosterior make_posterior() { return GpPosterior(test::random_points(15, 2, 5), Kernel{1.0, 1e-4}); }

TEST(GpPosterior, WeightsAtDataPointsAreUnitVectors) {
  const GpPosterior gp = make_posterior();
  for (int i = 0; i < gp.count(); ++i) {
    const Eigen::VectorXd w = gp.weights(gp.latent().row(i).transpose());
    Eigen::VectorXd e = Eigen::VectorXd::Zero(gp.count());
    e[i] = 1;
    EXPECT_LT((w - e).cwiseAbs().maxCoeff(), 1e-9) << "point " << i;
  }
}

TEST(GpPosterior, VarianceIsZeroAtDataAndOneFarAway) {
  const GpPosterior gp = make_posterior();
  for (int i = 0; i < gp.count(); ++i) EXPECT_NEAR(gp.variance(gp.latent().row(i).transpose()), 0.0, 1e-9);
  EXPECT_NEAR(gp.variance(Eigen::Vector2d(40.0, -35.0)), 1.0, 1e-12);
  // Between data points the variance is strictly between 0 and 1.
  const Eigen::Vector2d mid = 0.5 * (gp.latent().row(0) + gp.latent().row(1)).transpose();
  const double v = gp.variance(mid);
  EXPECT_GT(v, 0.0);
  EXPECT_LT(v, 1.0);
}

TEST(GpPosterior, InterpolatesDataExactlyAtTrainingPoints) {
  const GpPosterior gp = make_posterior();
  // Arbitrary (not smooth) data attached to the points: 3 columns.
  const Eigen::MatrixXd Y = test::random_points(gp.count(), 3, 99, 10.0);
  for (int i = 0; i < gp.count(); ++i) {
    const Eigen::VectorXd y = Y.transpose() * gp.weights(gp.latent().row(i).transpose());
    EXPECT_LT((y - Y.row(i).transpose()).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(GpPosterior, ReproducesASmoothFunctionBetweenPoints) {
  // A dense 1-D grid and a smooth function with length scale >> grid spacing: the posterior mean
  // between grid points is close to the function (a GP-draw-like smooth signal).
  const int n = 21;
  Eigen::MatrixXd X(n, 1);
  for (int i = 0; i < n; ++i) X(i, 0) = -2.0 + 0.2 * i;
  const GpPosterior gp(X, Kernel{0.6, 1e-8});
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) y[i] = std::sin(X(i, 0));
  for (double x : {-1.9, -0.55, 0.31, 1.77}) {
    const double mean = gp.weights(Eigen::VectorXd::Constant(1, x)).dot(y);
    EXPECT_NEAR(mean, std::sin(x), 1e-3) << "x = " << x;
  }
}

TEST(GpPosterior, BatchWeightsEqualSingle) {
  const GpPosterior gp = make_posterior();
  Eigen::MatrixXd P = test::random_points(7, 2, 123);
  P.row(3) = gp.latent().row(2);  // include a data point
  const Eigen::MatrixXd W = gp.weights_batch(P);
  ASSERT_EQ(W.rows(), gp.count());
  ASSERT_EQ(W.cols(), 7);
  for (int j = 0; j < 7; ++j) EXPECT_LT((W.col(j) - gp.weights(P.row(j).transpose())).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(gp.weights_batch(Eigen::MatrixXd::Zero(2, 3)), Error);
}

TEST(GpPosterior, PredictBatchEqualsSingleWeightsAndVariance) {
  const GpPosterior gp = make_posterior();
  Eigen::MatrixXd P = test::random_points(9, 2, 321);
  P.row(4) = gp.latent().row(1);  // a data point: its variance includes the nugget's prior
  const GpPosterior::Batch b = gp.predict_batch(P);
  ASSERT_EQ(b.weights.rows(), gp.count());
  ASSERT_EQ(b.variance.size(), 9);
  for (int j = 0; j < 9; ++j) {
    EXPECT_LT((b.weights.col(j) - gp.weights(P.row(j).transpose())).cwiseAbs().maxCoeff(), 1e-10) << j;
    EXPECT_NEAR(b.variance[j], gp.variance(P.row(j).transpose()), 1e-12) << j;
  }
  EXPECT_THROW(gp.predict_batch(Eigen::MatrixXd::Zero(2, 3)), Error);
}

TEST(GpPosterior, PredictBatchOfManyPointsEqualsThePerPointQueries) {
  // More points than one block of the batch (256), among them every data point and a point inside
  // every nugget taper (where k(x) gets its tapered nugget), and points far away.
  const GpPosterior gp(test::random_points(40, 3, 17), Kernel{0.8, 1e-3});
  const int n = gp.count(), m = 700;
  Eigen::MatrixXd P = test::random_points(m, 3, 18, 1.5);
  for (int i = 0; i < n; ++i) {
    P.row(i) = gp.latent().row(i);
    P.row(n + i) = gp.latent().row(i) + Eigen::RowVector3d(0.3, -0.2, 0.1) * gp.taper_radius()[i];
  }
  P.row(m - 1) = Eigen::RowVector3d(30, -20, 10);
  const GpPosterior::Batch b = gp.predict_batch(P);
  ASSERT_EQ(b.weights.cols(), m);
  for (int j = 0; j < m; ++j) {
    const Eigen::VectorXd x = P.row(j).transpose();
    EXPECT_LT((b.weights.col(j) - gp.weights(x)).cwiseAbs().maxCoeff(), 1e-10) << j;
    EXPECT_NEAR(b.variance[j], gp.variance(x), 1e-12) << j;
  }
  for (int i = 0; i < n; ++i) {
    EXPECT_LT((b.weights.col(i) - Eigen::VectorXd::Unit(n, i)).cwiseAbs().maxCoeff(), 1e-9) << "data point " << i;
    EXPECT_NEAR(b.variance[i], 0.0, 1e-9);
    EXPECT_GT(b.variance[n + i], 0.0) << "inside the taper of point " << i;
  }
  EXPECT_NEAR(b.variance[m - 1], 1.0, 1e-12);
  EXPECT_EQ(gp.predict_batch(Eigen::MatrixXd(0, 3)).weights.cols(), 0);
}

/// A grid of cols x rows cells on the plane through `origin` spanned by (orthonormal) u and v,
/// its coordinates from -span/2 to span/2 on both axes, and the same cells as points (m x q).
std::pair<GpPosterior::PlaneGrid, Eigen::MatrixXd> plane_grid(const Eigen::VectorXd& origin, const Eigen::VectorXd& u,
                                                              const Eigen::VectorXd& v, int cols, int rows, double span) {
  GpPosterior::PlaneGrid grid{origin, u, v, Eigen::VectorXd::LinSpaced(cols, -span / 2, span / 2),
                              Eigen::VectorXd::LinSpaced(rows, span / 2, -span / 2)};
  Eigen::MatrixXd points(cols * rows, origin.size());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) points.row(r * cols + c) = (origin + grid.u[c] * u + grid.v[r] * v).transpose();
  return {grid, points};
}

TEST(GpPosterior, PredictGridEqualsPredictBatchThroughLowRankLines) {
  // q = 3, data within a few lengthscales of a tilted plane; data point 0 on a cell (exact
  // interpolation there) and data point 7 on the plane 0.01 from another cell (inside its taper:
  // k gets the tapered nugget there, whose weight nugget K^-1 e_7 the grid must add).
  const Eigen::Vector3d origin(0.1, -0.2, 0.05);
  const Eigen::Vector3d u = Eigen::Vector3d(1, 1, 0).normalized(), v = Eigen::Vector3d(-1, 1, 2).normalized();
  const auto [grid, points] = plane_grid(origin, u, v, 72, 64, 5.0);
  const Eigen::Index on_cell = 5 * 72 + 9, near_cell = 20 * 72 + 30;
  Eigen::MatrixXd X = test::random_points(80, 3, 41, 2.0);
  X.row(0) = points.row(on_cell);
  X.row(7) = points.row(near_cell) + 0.01 * u.transpose();
  const GpPosterior gp(X, Kernel{1.0, 1e-4});
  ASSERT_LT(0.01, gp.taper_radius()[7]);
  const GpPosterior::Batch fast = gp.predict_grid(grid), exact = gp.predict_batch(points);
  ASSERT_EQ(fast.weights.rows(), gp.count());
  ASSERT_EQ(fast.weights.cols(), 72 * 64);
  ASSERT_EQ(fast.variance.size(), 72 * 64);
  EXPECT_GT(fast.rank, 0) << "the factorised lines, not the points one by one";
  EXPECT_LT(2 * 64 * fast.rank, 72 * 64);
  EXPECT_LT((fast.weights - exact.weights).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((fast.variance - exact.variance).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((fast.weights.col(on_cell) - Eigen::VectorXd::Unit(gp.count(), 0)).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_NEAR(fast.variance[on_cell], 0.0, 1e-9);
  // Far from the data: the weights vanish and the variance is 1.
  const GpPosterior::PlaneGrid far{Eigen::Vector3d(40, 0, 0), u, v, grid.u, grid.v};
  const GpPosterior::Batch distant = gp.predict_grid(far);
  EXPECT_LT(distant.weights.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(distant.variance.minCoeff(), 1.0, 1e-12);
}

TEST(GpPosterior, PredictGridGoesPointByPointForAxesThatAreNotOrthonormal) {
  const GpPosterior gp(test::random_points(30, 2, 43), Kernel{1.0, 1e-4});
  auto [grid, points] = plane_grid(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0.6, 0.8), 40, 30, 4.0);
  grid.axis_v = Eigen::Vector2d(0.5, 0.5);  // not unit, not orthogonal to u
  for (int r = 0; r < 30; ++r)
    for (int c = 0; c < 40; ++c) points.row(r * 40 + c) = (grid.u[c] * grid.axis_u + grid.v[r] * grid.axis_v).transpose();
  const GpPosterior::Batch fast = gp.predict_grid(grid), exact = gp.predict_batch(points);
  EXPECT_EQ(fast.rank, 0);
  EXPECT_EQ(fast.weights, exact.weights);
  EXPECT_EQ(fast.variance, exact.variance);
  grid.origin = Eigen::Vector3d::Zero();
  EXPECT_THROW(gp.predict_grid(grid), Error);
}

TEST(GpPosterior, LogDetAndConditionMatchEigenvalues) {
  const GpPosterior gp = make_posterior();
  const Eigen::MatrixXd K = covariance_matrix(gp.latent(), gp.kernel());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  EXPECT_NEAR(gp.log_det(), lambda.array().log().sum(), 1e-9);
  const double cond = lambda[lambda.size() - 1] / lambda[0];
  EXPECT_NEAR(gp.condition_estimate() / cond, 1.0, 0.05);
}

TEST(GpPosterior, DuplicatePointsNeedANugget) {
  Eigen::MatrixXd X = test::random_points(5, 2, 1);
  X.row(3) = X.row(1);
  EXPECT_THROW(GpPosterior(X, Kernel{1.0, 0.0}), Error);
  const GpPosterior gp(X, Kernel{1.0, 1e-4});
  // At a duplicated point the two copies share the weight.
  const Eigen::VectorXd w = gp.weights(X.row(1).transpose());
  EXPECT_NEAR(w[1] + w[3], 1.0, 1e-3);
  EXPECT_NEAR(w[1], w[3], 1e-3);
  EXPECT_THROW(GpPosterior(Eigen::MatrixXd(0, 2), Kernel{}), Error);
}

}  // namespace
}  // namespace matlas::gp
