// ComputeGate: bounded concurrency, first come first served, timeouts.
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "server/compute_gate.h"

namespace matlas::server {
namespace {

using namespace std::chrono_literals;

TEST(ComputeGate, NeverExceedsItsSlots) {
  ComputeGate gate(2);
  std::atomic<int> inside{0}, peak{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&] {
      for (int k = 0; k < 20; ++k) {
        auto slot = gate.acquire(5s);
        ASSERT_TRUE(slot);
        const int now = ++inside;
        int p = peak.load();
        while (now > p && !peak.compare_exchange_weak(p, now)) {
        }
        std::this_thread::sleep_for(100us);
        --inside;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(peak.load(), 2);
}

TEST(ComputeGate, TimesOutWhenFullAndServesWaitersInArrivalOrder) {
  ComputeGate gate(1);
  auto held = gate.acquire(1s);
  ASSERT_TRUE(held);
  EXPECT_FALSE(gate.acquire(20ms));  // full: gives up
  EXPECT_EQ(gate.waiting(), 0u);     // and leaves the queue

  std::mutex m;
  std::vector<int> order;
  std::vector<std::thread> waiters;
  for (int i = 0; i < 4; ++i) {
    waiters.emplace_back([&, i] {
      auto slot = gate.acquire(5s);
      ASSERT_TRUE(slot);
      std::lock_guard lock(m);
      order.push_back(i);
    });
    while (gate.waiting() < static_cast<std::size_t>(i + 1)) std::this_thread::sleep_for(1ms);
  }
  held.release();
  for (auto& t : waiters) t.join();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
}

}  // namespace
}  // namespace matlas::server
