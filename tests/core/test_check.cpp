// MATLAS_CHECK: a failed invariant throws InternalError naming the position, the condition and the
// values; a passing one evaluates its arguments once; a disabled DCHECK evaluates nothing.
#include <gtest/gtest.h>

#include <string>

#include "core/check.h"
#include "core/error.h"

namespace matlas {
namespace {

std::string failure_of(void (*f)()) {
  try {
    f();
  } catch (const InternalError& e) {
    return e.what();
  }
  return "";
}

TEST(Check, AFailedCheckNamesThePositionTheConditionAndTheValues) {
  const std::string eq = failure_of([] {
    const int weights = 4, count = 5;
    MATLAS_CHECK_EQ(weights, count);
  });
  EXPECT_NE(eq.find("internal check failed at "), std::string::npos) << eq;
  EXPECT_NE(eq.find("test_check.cpp:"), std::string::npos) << eq;
  EXPECT_NE(eq.find("weights == count (4 vs 5)"), std::string::npos) << eq;
  const std::string plain = failure_of([] { MATLAS_CHECK(1 + 1 == 3, "arithmetic holds"); });
  EXPECT_NE(plain.find("1 + 1 == 3 (arithmetic holds)"), std::string::npos) << plain;
  EXPECT_NE(failure_of([] { MATLAS_CHECK_LT(2.5, 1.0); }).find("2.5"), std::string::npos);
}

TEST(Check, InternalErrorsAreNotUserErrors) {
  // The command and the server tell a bug from a bad input by the type.
  EXPECT_THROW(MATLAS_CHECK(false), InternalError);
  try {
    MATLAS_CHECK(false);
  } catch (const Error&) {
    FAIL() << "a failed check must not read as a user's error";
  } catch (const InternalError&) {
  }
}

TEST(Check, PassingChecksEvaluateTheirArgumentsOnce) {
  int calls = 0;
  const auto next = [&] { return ++calls; };
  MATLAS_CHECK_EQ(next(), 1);
  MATLAS_CHECK(next() == 2);
  EXPECT_EQ(calls, 2);
}

TEST(Check, DchecksAreOnExactlyInCheckedBuilds) {
  int calls = 0;
  const auto touch = [&] {
    ++calls;
    return true;
  };
  MATLAS_DCHECK(touch());
#ifdef MATLAS_DCHECKS
  EXPECT_EQ(calls, 1);
  EXPECT_THROW(MATLAS_DCHECK_EQ(1, 2), InternalError);
#else
  EXPECT_EQ(calls, 0);
  EXPECT_NO_THROW(MATLAS_DCHECK_EQ(1, 2));
#endif
}

}  // namespace
}  // namespace matlas
