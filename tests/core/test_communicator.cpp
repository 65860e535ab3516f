// The serial communicator (one process: every collective is the identity), the error agreement
// built on it, the split of a pass into ranks' shares, and gather_arrays between ranks simulated
// by threads.
#include <barrier>
#include <cstring>
#include <functional>
#include <thread>

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
  std::vector<double> values{1.5, -2.0, 3.25}, low{1e-20, 0.0, -3e-19};
  c.sum(values);
  EXPECT_EQ(values, (std::vector<double>{1.5, -2.0, 3.25}));
  c.sum_compensated(values, low);
  EXPECT_EQ(values, (std::vector<double>{1.5, -2.0, 3.25}));
  EXPECT_EQ(low, (std::vector<double>{1e-20, 0.0, -3e-19}));
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

/// Ranks as threads of one process: each collective puts every rank's part in a shared slot
/// between two barriers (all_gather, gather and broadcast: what gather_arrays and
/// all_gather_arrays use).
class ThreadRanks {
public:
  explicit ThreadRanks(int size) : size_(size), slots_(static_cast<std::size_t>(size)), barrier_(size) {}

  class Rank final : public Communicator {
  public:
    Rank(ThreadRanks& ranks, int rank) : ranks_(ranks), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return ranks_.size_; }
    void sum(std::span<double>) override { ADD_FAILURE() << "not simulated"; }
    void sum_compensated(std::span<double>, std::span<double>) override { ADD_FAILURE() << "not simulated"; }
    std::vector<std::uint64_t> all_gather(std::uint64_t value) override {
      std::vector<std::uint64_t> all;
      for (const auto& bytes : exchange(std::as_bytes(std::span(&value, 1)))) {
        std::uint64_t v = 0;
        std::memcpy(&v, bytes.data(), sizeof v);
        all.push_back(v);
      }
      return all;
    }
    std::vector<std::byte> gather(std::span<const std::byte> bytes) override {
      std::vector<std::byte> all;
      for (const auto& part : exchange(bytes)) all.insert(all.end(), part.begin(), part.end());
      return rank_ == 0 ? all : std::vector<std::byte>{};
    }
    void broadcast(std::string& text) override {
      const auto all = exchange(std::as_bytes(std::span(text.data(), text.size())));
      text.assign(reinterpret_cast<const char*>(all[0].data()), all[0].size());
    }
    std::string first_error(const std::string& message) override { return message; }

  private:
    /// Every rank's bytes, in rank order.
    std::vector<std::vector<std::byte>> exchange(std::span<const std::byte> mine) {
      ranks_.slots_[static_cast<std::size_t>(rank_)].assign(mine.begin(), mine.end());
      ranks_.barrier_.arrive_and_wait();
      std::vector<std::vector<std::byte>> all = ranks_.slots_;
      ranks_.barrier_.arrive_and_wait();  // nobody overwrites a slot before everyone copied it
      return all;
    }
    ThreadRanks& ranks_;
    int rank_;
  };

  /// Runs body(communicator) on every rank at once.
  void run(const std::function<void(Communicator&)>& body) {
    std::vector<std::thread> threads;
    for (int r = 0; r < size_; ++r)
      threads.emplace_back([this, r, &body] {
        Rank rank(*this, r);
        body(rank);
      });
    for (auto& t : threads) t.join();
  }

private:
  int size_;
  std::vector<std::vector<std::byte>> slots_;
  std::barrier<> barrier_;
};

TEST(GatherArrays, RankZeroGetsEveryRanksArraysInRankOrder) {
  // Three ranks holding 2, 0 and 3 arrays of different lengths (one empty): rank 0 gets the five
  // in rank order, the others nothing.
  const std::vector<std::vector<std::vector<double>>> held{
      {{1.0, 2.0}, {3.0}}, {}, {{}, {4.0, 5.0, 6.0}, {7.0}}};
  std::vector<std::vector<std::vector<double>>> got(3);
  ThreadRanks ranks(3);
  ranks.run([&](Communicator& c) {
    got[static_cast<std::size_t>(c.rank())] = gather_arrays(c, held[static_cast<std::size_t>(c.rank())]);
  });
  const std::vector<std::vector<double>> expected{{1.0, 2.0}, {3.0}, {}, {4.0, 5.0, 6.0}, {7.0}};
  EXPECT_EQ(got[0], expected);
  EXPECT_TRUE(got[1].empty());
  EXPECT_TRUE(got[2].empty());
}

TEST(GatherArrays, AllGatherGivesEveryRankTheSameArraysInRankOrder) {
  const std::vector<std::vector<std::vector<std::uint32_t>>> held{{{7u}}, {{}, {1u, 2u}}};
  std::vector<std::vector<std::vector<std::uint32_t>>> got(2);
  ThreadRanks ranks(2);
  ranks.run([&](Communicator& c) {
    got[static_cast<std::size_t>(c.rank())] = all_gather_arrays(c, held[static_cast<std::size_t>(c.rank())]);
  });
  const std::vector<std::vector<std::uint32_t>> expected{{7u}, {}, {1u, 2u}};
  EXPECT_EQ(got[0], expected);
  EXPECT_EQ(got[1], expected);
}

TEST(GatherArrays, OneProcessKeepsItsArrays) {
  const std::vector<std::vector<float>> mine{{1.0f}, {}, {2.0f, 3.0f}};
  EXPECT_EQ(gather_arrays(serial_communicator(), mine), mine);
  EXPECT_EQ(all_gather_arrays(serial_communicator(), mine), mine);
}

}  // namespace
}  // namespace matlas
