#pragma once
// For tests of results that must not depend on the number of workers: f() run with one worker
// (core/parallel.h's loops run in the calling oneTBB arena, here one of a single thread).
#include <tbb/task_arena.h>

namespace matlas::test {

template <class F>
auto on_one_worker(const F& f) {
  decltype(f()) result;
  tbb::task_arena(1).execute([&] { result = f(); });
  return result;
}

}  // namespace matlas::test
