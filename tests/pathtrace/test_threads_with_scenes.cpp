// While a preview scene and a GI world exist, parallel loops still run on every worker thread
// asked for (issue 25): Embree's "threads=1" once capped the process's oneTBB pool to one thread
// for as long as a device lived, so every render ran on one core.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include "core/parallel.h"
#include "pathtrace/world.h"
#include "render/scene.h"

namespace matlas {
namespace {

/// Distinct threads that ran the items of a parallel loop whose items each sleep a while (so
/// that one thread cannot take them all before the others start).
std::size_t threads_used() {
  std::mutex m;
  std::set<std::thread::id> ids;
  parallel_for_each(0, 32, [&](std::size_t) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::lock_guard lock(m);
    ids.insert(std::this_thread::get_id());
  });
  return ids.size();
}

TEST(ThreadsWithScenes, ParallelLoopsUseEveryWorkerWhileScenesExist) {
  const unsigned asked = worker_count();
  if (asked < 2) GTEST_SKIP() << "one worker thread asked for (MATLAS_THREADS or a one-core machine)";
  const render::Scene preview{render::SceneDescription{}};
  pathtrace::SceneSpec spec;
  spec.camera.position = Vec3(0, 0, 10);
  spec.camera.target = Vec3::Zero();
  spec.environment.constant = Rgb::Constant(1.0);
  pathtrace::ObjectSpec o;
  o.shape = "sphere";
  spec.objects.push_back(o);
  const pathtrace::World world(spec);
  EXPECT_GE(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), asked);
  EXPECT_EQ(threads_used(), std::min<std::size_t>(asked, 32));
}

}  // namespace
}  // namespace matlas
