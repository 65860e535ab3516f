// The cost of fitting sparse samples (docs/ACQUISITION.md, target: under 1 s for n = 100 inputs
// and K = 80 samples) and of planning K directions, on a synthetic map: n latent points in q = 2,
// the GP's convex weights over them, inputs' values drawn smooth in x at K random rows. Each fit
// is reported beside one evaluation of the weights (the unit of the map search) measured in the
// same run, so the ratio says how many weight evaluations a fit costs.
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "acquisition/sample_plan.h"
#include "acquisition/sparse_fit.h"
#include "gp/convex_weights.h"
#include "gp/posterior.h"

namespace {

using namespace matlas;

struct SyntheticMap {
  std::unique_ptr<gp::GpPosterior> posterior;
  std::unique_ptr<gp::ConvexProjection> convex;
  acquisition::MapView view;
  Eigen::MatrixXd values;  // rows x n: inputs at the candidate rows
  Eigen::VectorXd cosine;

  SyntheticMap(int n, int rows) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0.0, 1.0);
    Eigen::MatrixXd X(n, 2);
    for (int i = 0; i < n; ++i) X.row(i) << 1.5 * g(rng), 1.5 * g(rng);
    values.resize(rows, n);
    cosine.resize(rows);
    for (int r = 0; r < rows; ++r) {
      const double a = g(rng), b = g(rng), peak = std::exp(2 * g(rng));
      cosine(r) = 0.2 + 0.8 * std::abs(std::sin(a));
      for (int i = 0; i < n; ++i) values(r, i) = 0.02 + peak * std::exp(-std::pow(X(i, 0) - a, 2) - std::pow(X(i, 1) - b, 2));
    }
    gp::Kernel k;
    posterior = std::make_unique<gp::GpPosterior>(X, k);
    const Eigen::MatrixXd centred = (values.rowwise() - values.colwise().mean()).transpose() *
                                    (values.rowwise() - values.colwise().mean());
    convex = std::make_unique<gp::ConvexProjection>(centred);
    view.latent = X;
    view.coefficients = [this](const Eigen::VectorXd& x) { return convex->from_centred(posterior->weights(x)); };
    view.variance = [this](const Eigen::VectorXd& x) { return posterior->variance(x); };
    view.metric = convex->metric();
  }
};

void BM_Weights(benchmark::State& state) {
  const SyntheticMap map(static_cast<int>(state.range(0)), 3);
  Eigen::VectorXd x(2);
  x << 0.3, -0.2;
  for (auto _ : state) benchmark::DoNotOptimize(map.view.coefficients(x));
}
BENCHMARK(BM_Weights)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_SparseFit(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), K = static_cast<int>(state.range(1));
  const bool combination = state.range(2) != 0;
  const SyntheticMap map(n, 3 * K);
  acquisition::SampleRows rows;
  const Eigen::VectorXd truth = map.view.coefficients((Eigen::VectorXd(2) << 0.4, 0.1).finished());
  for (int s = 0; s < K; ++s) {
    const Eigen::MatrixXd v = map.values.middleRows(3 * s, 3);
    rows.add(s, v, (v * truth).array() * 1.05, Eigen::Array3d::Zero(), map.cosine(3 * s));
  }
  acquisition::SparseFitOptions o;
  o.combination = combination;
  int evaluations = 0;
  for (auto _ : state) evaluations = acquisition::fit_rows(map.view, rows, o).evaluations;
  state.counters["evaluations"] = evaluations;
}
BENCHMARK(BM_SparseFit)->Args({100, 80, 0})->Args({100, 80, 1})->Args({100, 20, 1})->Unit(benchmark::kMillisecond);

void BM_SamplePlan(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), C = 5000;
  const SyntheticMap map(n, 3 * C);
  acquisition::PlanSpace space;
  space.values = map.values;
  space.cosine.resize(C);
  for (int c = 0; c < C; ++c) space.cosine(c) = map.cosine(3 * c);
  for (auto _ : state)
    benchmark::DoNotOptimize(acquisition::plan_directions(space, Eigen::VectorXd::Ones(n), nullptr, static_cast<int>(state.range(1))));
}
BENCHMARK(BM_SamplePlan)->Args({100, 80})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
