// allow_open_files: a soft limit on open descriptors below the hard one is raised to what is asked
// (and restored here afterwards); a limit that already allows it is left alone.
#include "core/file_io.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

namespace matlas {
namespace {

TEST(OpenFiles, RaisesTheSoftLimitTowardsTheHardOne) {
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &saved), 0);
  if (saved.rlim_max != RLIM_INFINITY && saved.rlim_max < 600) GTEST_SKIP() << "hard limit " << saved.rlim_max;
  rlimit low = saved;
  low.rlim_cur = 128;
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &low), 0);
  EXPECT_TRUE(allow_open_files(100));
  rlimit now{};
  ::getrlimit(RLIMIT_NOFILE, &now);
  EXPECT_EQ(now.rlim_cur, 128u);  // enough already: unchanged
  EXPECT_TRUE(allow_open_files(600));
  ::getrlimit(RLIMIT_NOFILE, &now);
  EXPECT_EQ(now.rlim_cur, 600u);
  if (saved.rlim_max != RLIM_INFINITY) {
    EXPECT_FALSE(allow_open_files(static_cast<std::size_t>(saved.rlim_max) + 1));  // beyond the hard limit
    ::getrlimit(RLIMIT_NOFILE, &now);
    EXPECT_EQ(now.rlim_cur, saved.rlim_max);  // as far as it goes
  }
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &saved), 0);
}

}  // namespace
}  // namespace matlas
