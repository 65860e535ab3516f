#pragma once
// parallel_for: splits [begin, end) into contiguous chunks run on the process's persistent
// worker threads (oneTBB). Persistent threads matter for libraries that keep per-thread state:
// OpenBLAS, for one, allocates its packing buffers per calling thread.
#include <cstddef>
#include <functional>

namespace matlas {

/// Number of worker threads to use (MATLAS_THREADS environment variable, else the core count).
unsigned worker_count();

/// Calls body(chunk_begin, chunk_end) on at most worker_count() disjoint contiguous chunks
/// covering [begin, end), each at least min_chunk long (except when the range is shorter), in
/// parallel. Safe to call from several threads at once and from inside a body. The first
/// exception thrown by a body is rethrown here.
void parallel_for(std::size_t begin, std::size_t end,
                  const std::function<void(std::size_t, std::size_t)>& body,
                  std::size_t min_chunk = 1);

/// Calls body(i) for every i in [begin, end) on the worker threads, handing out indices as
/// threads become free: for many small items of uneven cost, or when other threads (a reader,
/// another request) compete for the cores and a fixed split would leave one core waiting.
void parallel_for_each(std::size_t begin, std::size_t end, const std::function<void(std::size_t)>& body);

/// Calls body(first, size) for consecutive blocks of `block` items (the last one shorter) covering
/// [0, count), on the worker threads (parallel_for_each). The blocks depend on count and block
/// only, never on the number of workers: for elementwise work over the columns of a matrix.
void parallel_for_blocks(std::size_t count, std::size_t block,
                         const std::function<void(std::size_t, std::size_t)>& body);

/// Runs f on the calling thread as background work: the thread's scheduling priority is lowered
/// (Linux nice raised by 4, at most to 19; it stays lowered after f returns, so call this from a thread that does only
/// background work) and the parallel loops in f run in a low-priority oneTBB arena. The cores and
/// the worker threads then go to other work (a request a user waits for) first whenever there is
/// some, and all to f when there is none.
void run_in_background(const std::function<void()>& f);

}  // namespace matlas
