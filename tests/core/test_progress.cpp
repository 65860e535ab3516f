// The terminal bar's line: the fraction, the task's time, and the time left extrapolated from the
// rate so far (shown once enough is done to say).
#include <gtest/gtest.h>

#include <string>

#include "core/progress.h"

namespace matlas {
namespace {

TEST(Progress, TheLineExtrapolatesTheTimeLeft) {
  // A quarter done in 30 s: 90 s left.
  const std::string quarter = progress_line("perceptual distances", 25, 100, 30.0);
  EXPECT_NE(quarter.find(" 25.0%"), std::string::npos) << quarter;
  EXPECT_NE(quarter.find("30.0 s"), std::string::npos) << quarter;
  EXPECT_NE(quarter.find("about 1 min 30 s left"), std::string::npos) << quarter;
  EXPECT_NE(progress_line("x", 1, 4, 2.0).find("about 6 s left"), std::string::npos);
  EXPECT_NE(progress_line("x", 1, 2, 7200.0).find("about 2 h 00 min left"), std::string::npos);
}

TEST(Progress, NoTimeLeftBeforeItCanBeKnownOrAfterTheEnd) {
  EXPECT_EQ(progress_line("x", 0, 100, 5.0).find("left"), std::string::npos);    // nothing done
  EXPECT_EQ(progress_line("x", 1, 100, 5.0).find("left"), std::string::npos);    // 1 %: too early
  EXPECT_EQ(progress_line("x", 50, 100, 0.2).find("left"), std::string::npos);   // under a second
  EXPECT_EQ(progress_line("x", 100, 100, 9.0).find("left"), std::string::npos);  // done
  EXPECT_NE(progress_line("x", 100, 100, 9.0).find("100.0%"), std::string::npos);
  EXPECT_NE(progress_line("x", 5, 0, 1.0).find("  0.0%"), std::string::npos);   // no total
}

}  // namespace
}  // namespace matlas
