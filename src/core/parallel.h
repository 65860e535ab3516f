#pragma once
// parallel_for: splits [begin, end) into contiguous chunks over std::thread workers.
#include <algorithm>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace matlas {

/// Number of worker threads to use (MATLAS_THREADS environment variable, else the core count).
unsigned worker_count();

/// Calls body(chunk_begin, chunk_end) on disjoint chunks covering [begin, end), from up to
/// worker_count() threads. The first exception thrown by a body is rethrown here.
void parallel_for(std::size_t begin, std::size_t end,
                  const std::function<void(std::size_t, std::size_t)>& body,
                  std::size_t min_chunk = 1);

}  // namespace matlas
