// Rotated-ZH speed (docs/REALTIME.md): projection of one MERL-grid table to coefficients (L = 32,
// 32 view angles, the `matlas zonal` default; the viewer's, with its lobes and window per view
// angle), the per-band prefiltering of one environment, and
// the CPU reference's cost per shaded point, and the direct lights' light tables of a model (built
// once per model, then one per map point: MATLAS_BENCH_MODEL names a model file; skipped without).
// The table is a tabulated rough plastic (the same
// lookups as a measured BRDF); the environment is the installed studio map when present.
#include <benchmark/benchmark.h>

#include <cmath>

#include <cstdlib>
#include <memory>

#include "atlas/model_light_tables.h"
#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "render/assets.h"
#include "zonal/projection.h"
#include "manifold/model.h"
#include "zonal/shade.h"

namespace {

using namespace matlas;

const BrdfTable& table() {
  static const BrdfTable t = tabulate(RoughPlastic{Rgb(0.6, 0.2, 0.1), 0.08, 1.5, 1.0});
  return t;
}

render::Environment environment() {
  try {
    return render::Environment::load(resolve_environment("studio"));
  } catch (const Error&) {
    Image map(512, 256);
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 512; ++x)
        for (int c = 0; c < 3; ++c) map.pixel(x, y)[c] = (y < 60 && x > 300 && x < 320) ? 20.0f : 0.3f;
    return render::Environment(map);
  }
}

void BM_ProjectTable(benchmark::State& state) {
  zonal::ProjectionSettings s;
  s.bands = static_cast<int>(state.range(0));
  const zonal::ZonalProjector projector(s);
  for (auto _ : state) benchmark::DoNotOptimize(projector.project(table()).values.data());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ProjectTable)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The viewer's projection (L = 16, T = 32, the four lobes) without and with the window per view
/// angle (arg 1: zonal/ring_limit.h, floor 0.05): the limiter's share of a material's projection.
void BM_ViewerProjection(benchmark::State& state) {
  zonal::ProjectionSettings s;
  s.bands = 16;
  s.lobes = zonal::kDefaultLobes;
  if (state.range(0)) s.ring_floor = 0.05;
  const zonal::ZonalProjector projector(s);
  for (auto _ : state) benchmark::DoNotOptimize(projector.project(table()).values.data());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ViewerProjection)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PrefilterEnvironment(benchmark::State& state) {
  const render::Environment env = environment();
  zonal::PrefilterSettings s;
  s.bands = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const zonal::PrefilteredEnvironment filtered(env, s);
    benchmark::DoNotOptimize(filtered.map(0).data());
  }
}
BENCHMARK(BM_PrefilterEnvironment)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ShadePoint(benchmark::State& state) {
  zonal::ProjectionSettings s;
  s.bands = static_cast<int>(state.range(0));
  const zonal::ZonalProjector projector(s);
  const zonal::ZonalCoefficients c = projector.project(table());
  zonal::PrefilterSettings fs;
  fs.bands = s.bands;
  const zonal::PrefilteredEnvironment env(environment(), fs);
  double a = 0;
  for (auto _ : state) {
    a += 0.001;
    const Vec3 n(std::sin(a), std::cos(a), 0.0), wo(0.0, 0.35, 1.0);
    benchmark::DoNotOptimize(zonal::shade_point(projector.basis(), c, env, n, wo.normalized()));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ShadePoint)->Arg(16)->Arg(32)->Unit(benchmark::kMicrosecond);

}  // namespace

/// The model of MATLAS_BENCH_MODEL, or null.
const Model* bench_model() {
  static const std::unique_ptr<Model> model = [] {
    const char* path = std::getenv("MATLAS_BENCH_MODEL");
    return path ? std::make_unique<Model>(Model::open(path)) : nullptr;
  }();
  return model.get();
}

// Arg 0: building the light tables of every material and the mean (once per model); 1: the light
// table of a map point with every weight non-zero (each request of POST /api/realtime/lights).
void BM_ModelLightTables(benchmark::State& state) {
  const Model* model = bench_model();
  if (!model) {
    state.SkipWithError("MATLAS_BENCH_MODEL is not set");
    return;
  }
  if (state.range(0) == 0) {
    for (auto _ : state) benchmark::DoNotOptimize(atlas::ModelLightTables(*model).count());
    return;
  }
  const atlas::ModelLightTables tables(*model);
  const Eigen::VectorXd w = Eigen::VectorXd::Constant(model->count(), 1.0 / model->count());
  for (auto _ : state) benchmark::DoNotOptimize(tables.at(w).values().data());
  state.counters["MB"] = static_cast<double>(tables.dims().bins()) * 3 * 2 * (model->count() + 1) / 1e6;
}
BENCHMARK(BM_ModelLightTables)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
