#include "core/parallel.h"

#include <cstdlib>
#include <string>

namespace matlas {

unsigned worker_count() {
  if (const char* env = std::getenv("MATLAS_THREADS")) {
    const int n = std::atoi(env);
    if (n > 0) return static_cast<unsigned>(n);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

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
  std::exception_ptr failure;
  std::mutex failure_mutex;
  std::vector<std::thread> threads;
  threads.reserve(workers);
  for (std::size_t w = 0; w < workers; ++w) {
    const std::size_t lo = begin + count * w / workers;
    const std::size_t hi = begin + count * (w + 1) / workers;
    threads.emplace_back([&, lo, hi] {
      try {
        body(lo, hi);
      } catch (...) {
        std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    });
  }
  for (auto& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace matlas
