// ComputeGate: bounded concurrency, fair shares between clients (first come first served within
// one), a cap on each client's waiting requests, timeouts.
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
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

/// Starts a thread that waits for a slot as `client` and records its turn in `order`.
std::thread waiter(ComputeGate& gate, const std::string& client, std::mutex& m, std::vector<std::string>& order,
                   std::chrono::milliseconds hold = 0ms) {
  const std::size_t before = gate.waiting();
  std::thread t([&gate, client, &m, &order, hold] {
    auto slot = gate.acquire(10s, client);
    ASSERT_TRUE(slot);
    {
      std::lock_guard lock(m);
      order.push_back(client);
    }
    std::this_thread::sleep_for(hold);
  });
  while (gate.waiting() <= before) std::this_thread::sleep_for(1ms);
  return t;
}

TEST(ComputeGate, AClientWithFewerSlotsGoesFirst) {
  ComputeGate gate(ComputeGate::Options{1, 8});
  auto held = gate.acquire(1s, "flood");
  ASSERT_TRUE(held);
  std::mutex m;
  std::vector<std::string> order;
  std::vector<std::thread> ts;
  for (int i = 0; i < 3; ++i) ts.push_back(waiter(gate, "flood", m, order));
  ts.push_back(waiter(gate, "polite", m, order));  // arrives last
  held.release();
  for (auto& t : ts) t.join();
  ASSERT_EQ(order.size(), 4u);
  EXPECT_EQ(order.front(), "polite");  // first come, first served would put it last
}

TEST(ComputeGate, TheClientThatUsedTheSlotLeastLatelyGoesFirst) {
  ComputeGate gate(ComputeGate::Options{1, 8, 60s});
  {
    auto long_use = gate.acquire(1s, "long");
    std::this_thread::sleep_for(200ms);
  }
  {
    auto short_use = gate.acquire(1s, "short");
    std::this_thread::sleep_for(10ms);
  }
  auto held = gate.acquire(1s, "third");
  std::mutex m;
  std::vector<std::string> order;
  std::vector<std::thread> ts;
  ts.push_back(waiter(gate, "long", m, order));   // arrives first, but used 200 ms
  ts.push_back(waiter(gate, "short", m, order));  // used 10 ms
  held.release();
  for (auto& t : ts) t.join();
  EXPECT_EQ(order, (std::vector<std::string>{"short", "long"}));
}

TEST(ComputeGate, AClientsWaitingRequestsAreCapped) {
  ComputeGate gate(ComputeGate::Options{1, 2});
  auto held = gate.acquire(1s, "a");
  std::mutex m;
  std::vector<std::string> order;
  std::vector<std::thread> ts;
  ts.push_back(waiter(gate, "a", m, order));
  ts.push_back(waiter(gate, "a", m, order));
  // A third waiting request of "a" is refused at once, not after the timeout.
  ComputeGate::Refusal why = ComputeGate::Refusal::kNone;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(gate.acquire(5s, "a", &why));
  EXPECT_EQ(why, ComputeGate::Refusal::kRefused);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
  // Another client may still wait; a timeout says so.
  EXPECT_FALSE(gate.acquire(20ms, "b", &why));
  EXPECT_EQ(why, ComputeGate::Refusal::kTimedOut);
  held.release();
  for (auto& t : ts) t.join();
  EXPECT_EQ(order.size(), 2u);
}

}  // namespace
}  // namespace matlas::server
