#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/LU>

#include "eval/latent_fit.h"
#include "eval/statistics.h"

namespace matlas::eval {
namespace {

TEST(Statistics, RanksAverageTies) {
  const std::vector<double> v = {3.0, 1.0, 3.0, 2.0};
  const std::vector<double> r = average_ranks(v);
  EXPECT_EQ(r, (std::vector<double>{3.5, 1.0, 3.5, 2.0}));
}

TEST(Statistics, SpearmanOfMonotoneAndReversed) {
  const std::vector<double> a = {1, 2, 3, 4, 5}, b = {1, 4, 9, 16, 100}, c = {5, 4, 3, 2, 1};
  EXPECT_NEAR(spearman(a, b), 1.0, 1e-15);
  EXPECT_NEAR(spearman(a, c), -1.0, 1e-15);
  EXPECT_LT(pearson(a, b), 1.0);
  // Known value: ranks (1,2,3,4,5) vs (2,1,4,3,5): 1 - 6*4/(5*24) = 0.8.
  const std::vector<double> d = {20, 10, 40, 30, 50};
  EXPECT_NEAR(spearman(a, d), 0.8, 1e-12);
  EXPECT_TRUE(std::isnan(spearman(a, std::vector<double>(5, 1.0))));
}

TEST(Statistics, Summary) {
  const std::vector<double> v = {4, 1, 3, 2};
  const Summary s = summarize(v);
  EXPECT_EQ(s.mean, 2.5);
  EXPECT_EQ(s.median, 2.5);
  EXPECT_EQ(s.min, 1);
  EXPECT_EQ(s.max, 4);
}

}  // namespace
}  // namespace matlas::eval
