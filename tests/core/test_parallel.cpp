// parallel_for: every index exactly once in contiguous chunks, chunk limits, exceptions,
// nested calls and calls from several threads at once (the server does that).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/parallel.h"

#include <sys/resource.h>
#include <unistd.h>

namespace matlas {
namespace {

TEST(ParallelFor, CoversTheRangeOnceInAtMostWorkerCountChunks) {
  for (std::size_t count : {1u, 2u, 7u, 1000u}) {
    std::vector<std::atomic<int>> hits(count);
    std::atomic<std::size_t> chunks{0};
    parallel_for(10, 10 + count, [&](std::size_t lo, std::size_t hi) {
      ASSERT_LT(lo, hi);
      ++chunks;
      for (std::size_t i = lo; i < hi; ++i) ++hits[i - 10];
    });
    for (auto& h : hits) EXPECT_EQ(h.load(), 1);
    EXPECT_LE(chunks.load(), std::min<std::size_t>(count, worker_count()));
  }
}

TEST(ParallelFor, RespectsTheMinimumChunk) {
  std::atomic<std::size_t> chunks{0};
  parallel_for(0, 100, [&](std::size_t lo, std::size_t hi) {
    ++chunks;
    EXPECT_GE(hi - lo, 50u);
  }, 50);
  EXPECT_LE(chunks.load(), 2u);
}

TEST(ParallelFor, RethrowsAnExceptionFromABody) {
  EXPECT_THROW(parallel_for(0, 64, [&](std::size_t lo, std::size_t) {
                 if (lo == 0) throw std::runtime_error("boom");
               }),
               std::runtime_error);
}

TEST(ParallelFor, NestedAndConcurrentCallsComplete) {
  std::atomic<long> total{0};
  std::vector<std::thread> callers;
  for (int t = 0; t < 4; ++t)
    callers.emplace_back([&] {
      parallel_for(0, 8, [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i)
          parallel_for(0, 100, [&](std::size_t a, std::size_t b) { total += static_cast<long>(b - a); });
      });
    });
  for (auto& c : callers) c.join();
  EXPECT_EQ(total.load(), 4 * 8 * 100);
}

TEST(RunInBackground, LowersTheThreadsPriorityAndStillRunsLoopsOnAllWorkers) {
  // On a thread of its own: the lowered priority stays with the thread.
  std::atomic<int> covered{0};
  int nice_inside = 0, nice_before = 0;
  std::thread([&] {
    nice_before = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
    run_in_background([&] {
      nice_inside = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
      parallel_for_each(0, 1000, [&](std::size_t) { covered.fetch_add(1); });
      parallel_for(0, 1000, [&](std::size_t b, std::size_t e) { covered.fetch_add(static_cast<int>(e - b)); });
    });
  }).join();
  EXPECT_EQ(covered.load(), 2000);
  EXPECT_EQ(nice_inside, std::min(19, nice_before + 4));
  bool rethrown = false;  // an exception in f reaches the caller
  std::thread([&] {
    try {
      run_in_background([] { throw std::runtime_error("inside"); });
    } catch (const std::runtime_error&) {
      rethrown = true;
    }
  }).join();
  EXPECT_TRUE(rethrown);
}

}  // namespace
}  // namespace matlas
