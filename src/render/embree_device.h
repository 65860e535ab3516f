#pragma once
// The process's one Embree device, shared by every scene (previews, GI): created on first use and
// kept for the life of the process.
//
// It is created without a thread count. With Embree's TBB tasking, "threads=N" installs a
// process-wide tbb::global_control of N threads for as long as the device lives, and oneTBB obeys
// the smallest such limit: "threads=1" made every parallel loop of the process (pixels, GI paths,
// the server's work) run on one thread while a scene existed. Without it, Embree leaves oneTBB's
// pool to the process (core/parallel.h limits it to worker_count()).
#include <embree3/rtcore.h>

namespace matlas::render {

/// The shared device; throws matlas::Error if Embree cannot create one. Thread-safe.
RTCDevice embree_device();

}  // namespace matlas::render
