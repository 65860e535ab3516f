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
