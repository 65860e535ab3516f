#include "core/parallel.h"

#include <algorithm>
#include <cstdlib>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cerrno>
#include <sys/resource.h>
#include <unistd.h>

namespace matlas {

unsigned worker_count() {
  static const unsigned count = [] {
    if (const char* env = std::getenv("MATLAS_THREADS")) {
      const int n = std::atoi(env);
      if (n > 0) return static_cast<unsigned>(n);
    }
    return std::max(1u, std::thread::hardware_concurrency());
  }();
  return count;
}

namespace {

/// Limits oneTBB's pool to worker_count() threads for the life of the process.
void limit_pool() { static tbb::global_control limit(tbb::global_control::max_allowed_parallelism, worker_count()); }

}  // namespace

void parallel_for(std::size_t begin, std::size_t end,
                  const std::function<void(std::size_t, std::size_t)>& body,
                  std::size_t min_chunk) {
  if (end <= begin) return;
  const std::size_t count = end - begin;
  const std::size_t workers =
      std::min<std::size_t>(worker_count(), (count + min_chunk - 1) / std::max<std::size_t>(1, min_chunk));
  if (workers <= 1) {
    body(begin, end);
    return;
  }
  limit_pool();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, workers, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t w = r.begin(); w < r.end(); ++w)
          body(begin + count * w / workers, begin + count * (w + 1) / workers);
      },
      tbb::static_partitioner());
}

void parallel_for_each(std::size_t begin, std::size_t end, const std::function<void(std::size_t)>& body) {
  if (end <= begin) return;
  if (worker_count() <= 1 || end - begin == 1) {
    for (std::size_t i = begin; i < end; ++i) body(i);
    return;
  }
  limit_pool();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(begin, end, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
      },
      tbb::simple_partitioner());
}

void parallel_for_blocks(std::size_t count, std::size_t block,
                         const std::function<void(std::size_t, std::size_t)>& body) {
  if (count == 0) return;
  if (block == 0) block = count;
  const std::size_t blocks = (count + block - 1) / block;
  parallel_for_each(0, blocks, [&](std::size_t b) { body(b * block, std::min(block, count - b * block)); });
}

constexpr int kBackgroundNice = 4;

void run_in_background(const std::function<void()>& f) {
  // A failure to lower the priority only costs responsiveness: f runs all the same.
  // Relative to the thread's current value (a process run under nice stays below its callers).
  const auto tid = static_cast<id_t>(::gettid());
  errno = 0;
  const int current = ::getpriority(PRIO_PROCESS, tid);
  if (errno == 0) (void)::setpriority(PRIO_PROCESS, tid, std::min(19, current + kBackgroundNice));
  limit_pool();
  tbb::task_arena arena(static_cast<int>(worker_count()), 1, tbb::task_arena::priority::low);
  arena.execute(f);
}

}  // namespace matlas
