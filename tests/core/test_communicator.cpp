// The serial communicator (one process: every collective is the identity), the error agreement
// built on it, and the split of a pass into ranks' shares.
#include <gtest/gtest.h>

#include "core/check.h"
#include "core/communicator.h"
#include "core/error.h"

namespace matlas {
namespace {

TEST(SerialCommunicator, EveryCollectiveIsTheIdentity) {
  Communicator& c = serial_communicator();
  EXPECT_EQ(c.rank(), 0);
  EXPECT_EQ(c.size(), 1);
  EXPECT_TRUE(c.is_root());
  std::vector<double> values{1.5, -2.0, 3.25};
  c.sum(values);
  EXPECT_EQ(values, (std::vector<double>{1.5, -2.0, 3.25}));
  EXPECT_EQ(c.all_gather(42), (std::vector<std::uint64_t>{42}));
  const std::vector<std::byte> bytes{std::byte{1}, std::byte{2}, std::byte{3}};
  EXPECT_EQ(c.gather(bytes), bytes);
  std::string text = "rank 0's text";
  c.broadcast(text);
  EXPECT_EQ(text, "rank 0's text");
  EXPECT_EQ(c.first_error(""), "");
  EXPECT_EQ(c.first_error("a.binary: bad"), "a.binary: bad");
}

TEST(SerialCommunicator, RunCollectivelyRethrowsTheRanksOwnException) {
  Communicator& c = serial_communicator();
  int ran = 0;
  run_collectively(c, [&] { ++ran; });
  EXPECT_EQ(ran, 1);
  EXPECT_THROW(run_collectively(c, [] { throw Error("x.binary: non-finite value"); }), Error);
  EXPECT_THROW(run_collectively(c, [] { MATLAS_CHECK(false, "a bug"); }), InternalError);  // its own type
}

TEST(ShareOf, ContiguousNearlyEqualSharesCoverEverything) {
  for (const std::size_t items : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{356}})
    for (const int parts : {1, 2, 3, 16, 64}) {
      std::size_t next = 0, smallest = items, largest = 0;
      for (int p = 0; p < parts; ++p) {
        const auto [first, last] = share_of(items, p, parts);
        EXPECT_EQ(first, next);
        EXPECT_LE(first, last);
        smallest = std::min(smallest, last - first);
        largest = std::max(largest, last - first);
        next = last;
      }
      EXPECT_EQ(next, items);
      EXPECT_LE(largest - smallest, 1u);
    }
  EXPECT_THROW(share_of(10, 2, 2), InternalError);
}

}  // namespace
}  // namespace matlas
