// Render throughput: camera samples per second per core for the sphere and the bunny under an
// environment map, and the time of a 512x512, 64 spp preview. The material is a tabulated rough
// plastic on the MERL grid (the same lookups as a measured BRDF). Uses the installed assets when
// present (studio map, bunny); otherwise a synthetic map, and the bunny benchmark is skipped.
#include <benchmark/benchmark.h>

#include <cmath>
#include <optional>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "core/parallel.h"
#include "render/assets.h"
#include "render/material.h"
#include "render/render.h"
#include "render/scene.h"

namespace {

using namespace matlas;
using namespace matlas::render;

const BrdfTable& table() {
  static const BrdfTable t = tabulate(RoughPlastic{Rgb(0.6, 0.2, 0.1), 0.08, 1.5, 1.0});
  return t;
}

Environment environment() {
  try {
    return Environment::load(resolve_environment("studio"));
  } catch (const Error&) {
    Image map(64, 32);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 64; ++x)
        for (int c = 0; c < 3; ++c) map.pixel(x, y)[c] = (y < 8 && x > 40 && x < 44) ? 20.0f : 0.3f;
    return Environment(map);
  }
}

std::optional<Scene> make_scene(const std::string& object) {
  SceneDescription d;
  d.object = object;
  d.ground = true;
  std::optional<TriangleMesh> mesh;
  if (object != "sphere") {
    try {
      mesh = read_mesh(resolve_mesh(object));
    } catch (const Error&) {
      return std::nullopt;
    }
  }
  return Scene(d, std::move(mesh), environment());
}

void throughput(benchmark::State& state, const std::string& object) {
  const std::optional<Scene> scene = make_scene(object);
  if (!scene) {
    state.SkipWithError("assets not installed (scripts/install-assets.sh)");
    return;
  }
  RenderSettings s;
  s.width = s.height = 128;
  s.spp = 16;
  const TableMaterial material(table());
  RenderStats stats;
  for (auto _ : state) {
    Image im = matlas::render::render(*scene, material, s, null_progress(), &stats);
    benchmark::DoNotOptimize(im.rgb.data());
  }
  const double samples = static_cast<double>(s.width) * s.height * s.spp;
  state.counters["samples/s"] = benchmark::Counter(samples, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["samples/s/core"] =
      benchmark::Counter(samples / worker_count(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = worker_count();
}

void BM_RenderSphere(benchmark::State& state) { throughput(state, "sphere"); }
void BM_RenderBunny(benchmark::State& state) { throughput(state, "bunny"); }

void BM_Preview512x64spp(benchmark::State& state) {
  const std::optional<Scene> scene = make_scene("sphere");
  RenderSettings s;  // 512 x 512, 64 spp
  const TableMaterial material(table());
  for (auto _ : state) {
    Image im = matlas::render::render(*scene, material, s);
    benchmark::DoNotOptimize(im.rgb.data());
  }
}

}  // namespace

BENCHMARK(BM_RenderSphere)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderBunny)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Preview512x64spp)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

BENCHMARK_MAIN();
