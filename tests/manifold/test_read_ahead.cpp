#include "manifold/read_ahead.h"

#include <gtest/gtest.h>

#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace matlas {
namespace read_ahead_test {

using Requests = std::vector<std::pair<std::size_t, std::size_t>>;

/// Records the requests (first, count) a ReadAhead issues, from its thread.
struct Recorder {
  std::mutex mutex;
  Requests requests;
  auto issue() {
    return [this](std::size_t first, std::size_t count) {
      const std::lock_guard lock(mutex);
      requests.emplace_back(first, count);
    };
  }
  Requests taken() {
    const std::lock_guard lock(mutex);
    return requests;
  }
};

TEST(ReadAhead, AsksForTheWindowAtOnceThenAChunkAtATimeAsThePassMovesOn) {
  Recorder r;
  ReadAhead ahead(r.issue(), 100, 1000, 200, 50);
  ahead.drain();
  EXPECT_EQ(r.taken(), (Requests{{100, 200}}));  // the window from the start
  EXPECT_EQ(ahead.issued(), 300u);
  ahead.advance(160);  // window now ends at 360: two chunks, the second cut at the window
  ahead.drain();
  EXPECT_EQ(r.taken(), (Requests{{100, 200}, {300, 50}, {350, 10}}));
  ahead.advance(150);  // backwards: nothing new
  ahead.drain();
  EXPECT_EQ(r.taken().size(), 3u);
}

TEST(ReadAhead, CoversTheRangeInOrderWithoutGapsAndNeverPastItsEnd) {
  Recorder r;
  ReadAhead ahead(r.issue(), 7, 1003, 64, 16);
  for (std::size_t p = 7; p <= 1003; p += 37) {
    ahead.advance(p);
    ahead.drain();
  }
  ahead.advance(5000);  // past the end: clamped
  ahead.drain();
  const Requests got = r.taken();
  ASSERT_FALSE(got.empty());
  std::size_t next = 7;
  for (const auto& [first, count] : got) {
    EXPECT_EQ(first, next);
    EXPECT_GT(count, 0u);
    EXPECT_LE(count, first == 7 ? 64u : 16u);
    next = first + count;
  }
  EXPECT_EQ(next, 1003u);
  EXPECT_EQ(ahead.issued(), 1003u);
}

TEST(ReadAhead, ReleasesWhatLiesBehindThePassAChunkOrMoreAtATime) {
  Recorder asked, released;
  ReadAhead ahead(asked.issue(), 0, 1000, 100, 20, released.issue());
  ahead.advance(15);  // less than a chunk behind: nothing released yet
  ahead.drain();
  EXPECT_TRUE(released.taken().empty());
  ahead.advance(45);
  ahead.drain();
  ahead.advance(46);  // one more value: not yet a chunk since the last release
  ahead.drain();
  ahead.advance(130);
  ahead.drain();
  EXPECT_EQ(released.taken(), (Requests{{0, 45}, {45, 85}}));
  // Never ahead of the pass, and what was released had been asked for.
  EXPECT_LE(45u + 85u, ahead.issued());
}

TEST(ReadAhead, AnEmptyRangeAsksForNothing) {
  Recorder r;
  {
    ReadAhead ahead(r.issue(), 40, 40, 8, 8);
    ahead.advance(100);
    ahead.drain();
    EXPECT_EQ(ahead.issued(), 40u);
  }
  EXPECT_TRUE(r.taken().empty());
}

TEST(ReadAhead, ARequestThatThrowsEndsTheReadAhead) {
  int calls = 0;
  ReadAhead ahead(
      [&calls](std::size_t, std::size_t) {
        ++calls;
        throw std::runtime_error("no such file");
      },
      0, 1000, 100, 10);
  ahead.drain();
  ahead.advance(500);
  ahead.drain();
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(ahead.issued(), 1000u);
}

}  // namespace read_ahead_test
}  // namespace matlas
