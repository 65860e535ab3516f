#include "core/vector_math.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace matlas {
namespace {

/// Relative difference in units of the double epsilon.
double ulps(double got, double want) {
  if (got == want) return 0.0;
  return std::abs(got - want) / (std::abs(want) * std::numeric_limits<double>::epsilon());
}

/// Every length from 0 to 37 (the vector bodies and all their tails), values over the domain a
/// caller passes: -u for the kernel (u = squared distance / l^2 up to ~100), small arguments for
/// expm1, (0, 2] for the barrier's log.
template <class Vector, class Scalar>
void expect_matches(Vector vector, Scalar scalar, double lo, double hi, double max_ulps) {
  for (std::size_t count = 0; count <= 37; ++count) {
    std::vector<double> v(count + 1);
    for (std::size_t i = 0; i < count; ++i) v[i] = lo + (hi - lo) * static_cast<double>(i * 7919 % 101) / 100.0;
    v[count] = 12345.0;  // past the end: must stay untouched
    const std::vector<double> in = v;
    vector(v.data(), count);
    for (std::size_t i = 0; i < count; ++i) EXPECT_LE(ulps(v[i], scalar(in[i])), max_ulps) << in[i];
    EXPECT_EQ(v[count], 12345.0);
  }
}

TEST(VectorMath, ExpMatchesLibmOnEveryLengthAndLeavesTheRestAlone) {
  expect_matches(exp_in_place, [](double x) { return std::exp(x); }, -100.0, 0.0, 4.0);
  std::vector<double> zero{0.0};
  exp_in_place(zero.data(), 1);
  EXPECT_EQ(zero[0], 1.0);  // the kernel's diagonal is exactly 1
}

TEST(VectorMath, Expm1IsAccurateNearZero) {
  expect_matches(expm1_in_place, [](double x) { return std::expm1(x); }, -1e-6, 0.0, 4.0);
  expect_matches(expm1_in_place, [](double x) { return std::expm1(x); }, -50.0, 0.0, 4.0);
}

TEST(VectorMath, LogMatchesLibm) {
  expect_matches(log_in_place, [](double x) { return std::log(x); }, 1e-12, 2.0, 4.0);
}

}  // namespace
}  // namespace matlas
