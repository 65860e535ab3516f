// Cost of the albedo operator in a build (docs/BENCHMARKS.md): its setup before the pass's first
// block, and the pass's albedo products (each material's row of a 4096-column block times the
// operator's entries for those columns, as manifold/gram.cpp does) over all 3 * bins columns for
// n = 100 materials, on one thread. Arg 0: the per-theta_h-bin half-vector rule (the default);
// arg 1: the 64x64 cosine grid of directions that the builds used before it, for comparison.
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "brdf/albedo.h"
#include "brdf/albedo_operator.h"

using namespace matlas;

namespace {

using Operator = Eigen::SparseMatrix<double, Eigen::RowMajor>;
constexpr int kAngles = 90;

/// The previous operator: cosine-distributed directions, nearest bin, equal weights.
Operator cosine_grid_operator(const MerlDims& dims, int resolution) {
  const std::vector<Vec3> dirs = cosine_quadrature(resolution);
  const double weight = kPi / static_cast<double>(dirs.size());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(dirs.size() * kAngles);
  for (int t = 0; t < kAngles; ++t) {
    const Vec3 wo = direction_at_theta((t + 0.5) / kAngles * (kPi / 2.0));
    for (const Vec3& wi : dirs) entries.emplace_back(static_cast<int>(bin_of(dims, wi, wo)), t, weight);
  }
  Operator a(static_cast<Eigen::Index>(dims.bins()), kAngles);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

Operator make(int which) {
  return which == 0 ? albedo_operator(MerlDims{}, kAngles) : cosine_grid_operator(MerlDims{}, 64);
}

void BM_AlbedoOperatorSetup(benchmark::State& state) {
  std::size_t nnz = 0;
  for (auto _ : state) nnz = static_cast<std::size_t>(make(static_cast<int>(state.range(0))).nonZeros());
  state.counters["nonzeros"] = static_cast<double>(nnz);
}
BENCHMARK(BM_AlbedoOperatorSetup)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void BM_AlbedoProductsPerPass(benchmark::State& state) {
  const Operator op = make(static_cast<int>(state.range(0)));
  const MerlDims dims{};
  const std::size_t n = 100, step = 4096, bins = dims.bins(), total = 3 * bins;
  std::vector<double> block(n * step);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double& v : block) v = u(rng);
  struct Entry {
    std::size_t column, slot;
    double weight;
  };
  std::vector<double> out(n * kAngles * 3);
  for (auto _ : state) {
    for (std::size_t first = 0; first < total; first += step) {
      const std::size_t count = std::min(step, total - first);
      std::vector<Entry> entries;
      for (std::size_t j = 0; j < count; ++j) {
        const std::size_t v = first + j;
        for (Operator::InnerIterator it(op, static_cast<Eigen::Index>(v % bins)); it; ++it)
          entries.push_back({j, static_cast<std::size_t>(it.col()) * 3 + v / bins, it.value()});
      }
      for (std::size_t i = 0; i < n; ++i) {
        const double* row = block.data() + i * step;
        double* o = out.data() + i * kAngles * 3;
        for (const Entry& e : entries) o[e.slot] += e.weight * row[e.column];
      }
    }
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_AlbedoProductsPerPass)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
