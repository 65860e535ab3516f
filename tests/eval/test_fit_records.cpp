// The study's fit records (exchanged between ranks): every value comes back bit for bit, and a
// record of the wrong kind or length is refused.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/check.h"
#include "eval/fit_records.h"

namespace matlas::eval {
namespace {

TEST(FitRecords, AFitComesBackBitForBit) {
  Eigen::MatrixXd latent(3, 2);
  latent << 0.1, -2.5, std::nextafter(1.0, 2.0), 1e-300, -0.0, 7.25;
  double seconds = 0, likelihood = 0;
  Eigen::MatrixXd back;
  read_fit_record(fit_record(1.5, -1234.5678, latent), seconds, likelihood, back);
  EXPECT_EQ(seconds, 1.5);
  EXPECT_EQ(likelihood, -1234.5678);
  EXPECT_EQ(back, latent);
  EXPECT_TRUE(std::signbit(back(2, 0)));  // the -0.0 keeps its sign
}

TEST(FitRecords, AProjectionComesBackBitForBit) {
  GramProjection p;
  p.x = Eigen::Vector2d(0.25, -1.0 / 3.0);
  p.coefficients = Eigen::Vector4d(0.5, 0.25, 0.25, 0.0);
  p.residual_squared = 3.0e-5;
  p.candidates = {Eigen::Vector4d(1, 0, 0, 0), Eigen::VectorXd(), Eigen::Vector4d(0.1, 0.2, 0.3, 0.4)};
  GramProjection back;
  double seconds = 0;
  read_projection_record(projection_record(0.75, p), seconds, back);
  EXPECT_EQ(seconds, 0.75);
  EXPECT_EQ(back.x, p.x);
  EXPECT_EQ(back.coefficients, p.coefficients);
  EXPECT_EQ(back.residual_squared, p.residual_squared);
  ASSERT_EQ(back.candidates.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(back.candidates[k], p.candidates[k]) << k;
}

TEST(FitRecords, AWrongRecordIsRefused) {
  const std::vector<double> fit = fit_record(1.0, 2.0, Eigen::MatrixXd::Ones(2, 2));
  GramProjection p;
  double seconds = 0;
  EXPECT_THROW(read_projection_record(fit, seconds, p), InternalError);  // lengths do not add up
  std::vector<double> shorter(fit.begin(), fit.end() - 1);
  double likelihood = 0;
  Eigen::MatrixXd latent;
  EXPECT_THROW(read_fit_record(shorter, seconds, likelihood, latent), InternalError);
  std::vector<double> longer = fit;
  longer.push_back(0.0);
  EXPECT_THROW(read_fit_record(longer, seconds, likelihood, latent), InternalError);
}

}  // namespace
}  // namespace matlas::eval
