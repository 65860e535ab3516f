// The server's map layers (POST /api/map) without HTTP: a 128 x 128 grid over a model's map, its
// weights and variances, and each layer as PNG bytes (atlas/map_layers.h), on a real model:
//   MATLAS_BENCH_MODEL=/tmp/m.matlas build/bench/bench_map_layers
// The model's own interpolation mode is used (convex for models built by default). Baseline in
// the same run: BM_GridWeightsPerPoint, the grid's weights the way they were computed before the
// batched convex solve (the batched GP, then every point's convex weights solved on its own from
// the cold start, in parallel), but with today's solver; the former binary as a whole is timed
// end to end by bench/map_layer_latency.py.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

#include "atlas/latent_plane.h"
#include "atlas/map_layers.h"
#include "core/parallel.h"
#include "core/tiled_products.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"

namespace {

using namespace matlas;

constexpr int kSide = 128;

const Model* bench_model() {
  static const std::unique_ptr<Model> model = [] {
    const char* path = std::getenv("MATLAS_BENCH_MODEL");
    if (!path) {
      std::fprintf(stderr, "set MATLAS_BENCH_MODEL to a .matlas file\n");
      std::exit(2);
    }
    return std::make_unique<Model>(Model::open(path));
  }();
  return model.get();
}

/// The plane the browser shows first: the data's box plus a margin, axes 0 and 1.
atlas::LatentPlane bench_plane() { return atlas::LatentPlane::automatic(*bench_model()); }

/// The grid's points, row-major (as latent_grid lays them out).
Eigen::MatrixXd grid_points(const atlas::LatentPlane& plane, int side = kSide) {
  Eigen::MatrixXd points(side * side, bench_model()->dim());
  const Eigen::VectorXd u = plane.cell_u(side), v = plane.cell_v(side);
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c) points.row(r * side + c) = plane.point(u[c], v[r]).transpose();
  return points;
}

void BM_GridWeightsPerPoint(benchmark::State& state) {
  const Model& model = *bench_model();
  const Eigen::MatrixXd points = grid_points(bench_plane());
  for (auto _ : state) {
    gp::GpPosterior::Batch b = model.posterior().predict_batch(points);
    parallel_for(0, static_cast<std::size_t>(b.weights.cols()), [&](std::size_t lo, std::size_t hi) {
      for (std::size_t j = lo; j < hi; ++j) {
        const auto col = static_cast<Eigen::Index>(j);
        b.weights.col(col) = model.weights_from_gp(b.weights.col(col));
      }
    }, 16);
    benchmark::DoNotOptimize(b.weights.data());
  }
  state.SetLabel(std::string(to_string(model.interpolation())) + ", n = " + std::to_string(model.count()));
}
BENCHMARK(BM_GridWeightsPerPoint)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GpBatch(benchmark::State& state) {
  const Model& model = *bench_model();
  const Eigen::MatrixXd points = grid_points(bench_plane(), static_cast<int>(state.range(0)));
  for (auto _ : state) {
    gp::GpPosterior::Batch b = model.posterior().predict_batch(points);
    benchmark::DoNotOptimize(b.weights.data());
  }
}
BENCHMARK(BM_GpBatch)->Arg(kSide)->Arg(24)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The same cells through the kernel's separability on the plane (GpPosterior::predict_grid, what
/// the map's layers use); the label gives its largest differences from BM_GpBatch's.
void BM_GpGrid(benchmark::State& state) {
  const Model& model = *bench_model();
  const atlas::LatentPlane plane = bench_plane();
  const auto side = static_cast<int>(state.range(0));
  const gp::GpPosterior::PlaneGrid grid{plane.origin, plane.axis_u, plane.axis_v, plane.cell_u(side), plane.cell_v(side)};
  for (auto _ : state) {
    gp::GpPosterior::Batch b = model.posterior().predict_grid(grid);
    benchmark::DoNotOptimize(b.weights.data());
  }
  const gp::GpPosterior::Batch exact = model.posterior().predict_batch(grid_points(plane, side));
  const gp::GpPosterior::Batch fast = model.posterior().predict_grid(grid);
  char label[128];
  std::snprintf(label, sizeof label, "rank %d; max |dw| %.2g (of %.2g), max |dvariance| %.2g", static_cast<int>(fast.rank),
                (fast.weights - exact.weights).cwiseAbs().maxCoeff(), exact.weights.cwiseAbs().maxCoeff(),
                (fast.variance - exact.variance).cwiseAbs().maxCoeff());
  state.SetLabel(label);
}
BENCHMARK(BM_GpGrid)->Arg(kSide)->Arg(24)->Unit(benchmark::kMillisecond)->UseRealTime();

/// BM_GpBatch's product alone (n x n by n x cells, random matrices; OpenBLAS's dgemm in tiles of
/// 256 columns on the workers, predict_batch's block): the bound its kernel values, dsymm and
/// variances are held against. Counter: GFLOP/s.
void BM_ProductAlone(benchmark::State& state) {
  const int n = bench_model()->count(), cells = kSide * kSide;
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n), b = Eigen::MatrixXd::Random(n, cells);
  Eigen::MatrixXd c(n, cells);
  for (auto _ : state) {
    blas::tiled_product(n, cells, n, 1.0, a.data(), n, b.data(), n, c.data(), n, 256);
    benchmark::DoNotOptimize(c.data());
  }
  state.counters["GFLOPs"] = benchmark::Counter(2.0 * n * n * cells * 1e-9 * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ProductAlone)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GridWeights(benchmark::State& state) {
  const Model& model = *bench_model();
  const atlas::LatentPlane plane = bench_plane();
  for (auto _ : state) {
    const atlas::LatentGrid g = atlas::latent_grid(model, plane, kSide, kSide);
    benchmark::DoNotOptimize(g.weights.data());
  }
}
BENCHMARK(BM_GridWeights)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MapLayer(benchmark::State& state) {
  const Model& model = *bench_model();
  const PlausibilityProbe probe(model, 256);  // the server's map probe
  const atlas::LatentPlane plane = bench_plane();
  const auto layer = static_cast<atlas::MapLayer>(state.range(0));
  for (auto _ : state) {
    const std::string png = atlas::map_layer_png(model, plane, kSide, kSide, layer, &probe);
    benchmark::DoNotOptimize(png.data());
  }
  state.SetLabel(atlas::to_string(layer));
}
BENCHMARK(BM_MapLayer)
    ->Arg(static_cast<int>(atlas::MapLayer::albedo))
    ->Arg(static_cast<int>(atlas::MapLayer::variance))
    ->Arg(static_cast<int>(atlas::MapLayer::plausibility))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
