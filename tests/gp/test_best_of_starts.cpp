// BestOfStarts, the multi-start bookkeeping of the dense and the sparse optimisation: the best
// result kept (the first of equals), totals over the starts, stopping at a target or the time
// limit, each start's share of the time.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "gp/optimize_run.h"

namespace matlas::gp::detail {
namespace {

OptimizeResult start_result(double value, int iterations, const char* reason = "converged") {
  OptimizeResult r;
  r.value = value;
  r.iterations = iterations;
  r.evaluations = 2 * iterations;
  r.stop_reason = reason;
  return r;
}

TEST(BestOfStarts, KeepsTheFirstBestAndCountsEveryStart) {
  OptimizeOptions o;
  o.starts = 4;
  BestOfStarts starts(o);
  EXPECT_TRUE(starts.add(start_result(-5.0, 3), 0));
  EXPECT_TRUE(starts.add(start_result(-2.0, 4), 1));
  EXPECT_FALSE(starts.add(start_result(-2.0, 5), 2));  // equal: the first stays
  EXPECT_FALSE(starts.add(start_result(-9.0, 6), 3));
  EXPECT_FALSE(starts.done());
  const OptimizeResult best = starts.finish();
  EXPECT_EQ(best.value, -2.0);
  EXPECT_EQ(best.best_start, 1);
  EXPECT_EQ(best.iterations, 18);
  EXPECT_EQ(best.evaluations, 36);
  EXPECT_EQ(best.stop_reason, "converged (best of 4 starts: start 2)");
}

TEST(BestOfStarts, ATargetOrTheTimeLimitEndsTheStarts) {
  OptimizeOptions o;
  o.starts = 3;
  BestOfStarts target(o);
  target.add(start_result(1.0, 1, "target value reached"), 0);
  EXPECT_TRUE(target.done());
  BestOfStarts time(o);
  time.add(start_result(1.0, 1, "time limit reached"), 0);
  EXPECT_TRUE(time.done());
  o.starts = 1;
  BestOfStarts one(o);
  one.add(start_result(1.0, 1), 0);
  EXPECT_EQ(one.finish().stop_reason, "converged");  // one start: nothing to say
}

TEST(BestOfStarts, EachStartGetsWhatIsLeftOfTheTimeLimit) {
  OptimizeOptions o;
  o.starts = 3;
  o.time_limit_seconds = 0.2;
  BestOfStarts starts(o);
  ASSERT_TRUE(starts.start(0).has_value());
  EXPECT_LE(starts.start(0)->time_limit_seconds, 0.2);
  EXPECT_GT(starts.start(0)->time_limit_seconds, 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  EXPECT_FALSE(starts.start(1).has_value());  // spent: no second start
  EXPECT_TRUE(starts.start(0).has_value());    // the first always runs
  EXPECT_EQ(starts.start(0)->time_limit_seconds, 1e-9);
  o.time_limit_seconds = 0;  // no limit: the options as given
  EXPECT_EQ(BestOfStarts(o).start(2)->time_limit_seconds, 0.0);
}

}  // namespace
}  // namespace matlas::gp::detail
