// L-BFGS (analytic gradient) versus Hooke-Jeeves (the paper's derivative-free pattern search) on a
// realistic GP-LVM problem: n = 100 synthetic "BRDF-like" materials, each a mixture of smooth
// basis curves over a (theta_h, theta_d) grid of 20000 bins, log-mapped like MERL data; the Gram
// is computed from those 20000 columns and then D' = 4.37e6 (MERL's column count) is used.
//
//   BM_Evaluation/q/grad     one likelihood evaluation (grad = 1: with gradient; 0: value only)
//   BM_Optimizers/q          Hooke-Jeeves to convergence (the baseline), then L-BFGS from the same
//                            PCA start until it reaches Hooke-Jeeves' final L, with 1 start
//                            (lbfgs1_*) and with 5 scaled starts (lbfgs5_*); counters give the
//                            times, whether HJ's L was reached, and t(L-BFGS) / t(HJ). Also
//                            L-BFGS (1 start) run to its own convergence (lbfgs_full_*).
//
// Environment: MATLAS_BENCH_HJ_TOL (Hooke-Jeeves tolerance, default 1e-7),
//              MATLAS_BENCH_HJ_MAX_SECONDS (cap on its run time, default 0 = none).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <random>
#include <string>

#include "core/blas.h"
#include "core/tiled_cholesky.h"
#include "core/tiled_products.h"
#include "gp/initialize.h"
#include "gp/likelihood.h"
#include "gp/optimize.h"

namespace {

using namespace matlas::gp;

constexpr int kItems = 100;
constexpr int kThetaH = 200, kThetaD = 100;  // 20000 columns
constexpr double kMerlColumns = 4.37e6;

/// Rows: log(1 + f cos) of a diffuse + specular-lobe + Fresnel-like mixture with random albedo,
/// lobe width, lobe strength and grazing boost; a smooth 4-parameter family (like measured BRDFs,
/// whose principal axes are diffuse colour, roughness and specularity).
Eigen::MatrixXd synthetic_brdfs() {
  std::mt19937_64 rng(2018);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::MatrixXd Z(kItems, kThetaH * kThetaD);
  for (int i = 0; i < kItems; ++i) {
    const double diffuse = 0.02 + 0.5 * unit(rng);
    const double width = std::exp(std::log(0.02) + unit(rng) * (std::log(0.6) - std::log(0.02)));
    const double strength = std::exp(std::log(0.05) + unit(rng) * std::log(200.0));
    const double fresnel = unit(rng);
    for (int d = 0; d < kThetaD; ++d) {
      const double theta_d = (d + 0.5) / kThetaD * (M_PI / 2);
      const double f = 1.0 + fresnel * std::pow(1.0 - std::cos(theta_d), 5.0) * 10.0;
      for (int h = 0; h < kThetaH; ++h) {
        const double theta_h = std::pow((h + 0.5) / kThetaH, 2.0) * (M_PI / 2);  // MERL-like sqrt spacing
        const double t = std::tan(theta_h) / width;
        const double lobe = strength * std::exp(-t * t) / (width * width);
        const double value = diffuse / M_PI + f * lobe;
        Z(i, d * kThetaH + h) = std::log1p(value * std::cos(theta_h));
      }
    }
  }
  return Z;
}

const LikelihoodProblem& problem() {
  static const LikelihoodProblem p = [] {
    const Eigen::MatrixXd Z = synthetic_brdfs();
    const Eigen::MatrixXd centred = Z.rowwise() - Z.colwise().mean();
    LikelihoodProblem lp;
    lp.gram = centred * centred.transpose();
    lp.columns = kMerlColumns;
    return lp;
  }();
  return p;
}

double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

void BM_Evaluation(benchmark::State& state) {
  const int q = static_cast<int>(state.range(0));
  const bool gradient = state.range(1) != 0;
  LikelihoodEvaluator evaluator(problem());
  const Eigen::MatrixXd X = pca_initialization(problem(), q);
  Eigen::MatrixXd G;
  for (auto _ : state) benchmark::DoNotOptimize(evaluator.normalized(X, gradient ? &G : nullptr));
}
BENCHMARK(BM_Evaluation)->ArgsProduct({{2, 5}, {0, 1}})->Unit(benchmark::kMicrosecond);

/// K^-1 from the Cholesky factor at n = 100: blas::inverse_from_cholesky (recursive triangular
/// inverse) against LAPACK's dtrtri + dlauum from OpenBLAS (what dpotri calls), same run; the
/// counter is LAPACK's time over the recursive one.
void BM_InverseFromCholesky(benchmark::State& state) {
  const int n = 100, reps = 200;
  const matlas::blas::Library& lib = matlas::blas::openblas();
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  Eigen::MatrixXd L = a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  int info = 0;
  lib.dpotrf("L", &n, L.data(), &n, &info);
  Eigen::MatrixXd w;
  double t_recursive = 0, t_lapack = 0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) {
      w = L;
      matlas::blas::inverse_from_cholesky(n, w.data(), n);
    }
    auto t1 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) {
      w = L;
      lib.dtrtri("L", "N", &n, w.data(), &n, &info);
      lib.dlauum("L", &n, w.data(), &n, &info);
    }
    auto t2 = std::chrono::steady_clock::now();
    t_recursive += std::chrono::duration<double>(t1 - t0).count();
    t_lapack += std::chrono::duration<double>(t2 - t1).count();
  }
  const double calls = static_cast<double>(state.iterations()) * reps;
  state.counters["recursive_us"] = t_recursive / calls * 1e6;
  state.counters["lapack_us"] = t_lapack / calls * 1e6;
  state.counters["lapack_over_recursive"] = t_lapack / t_recursive;
}
BENCHMARK(BM_InverseFromCholesky)->Iterations(5)->UseRealTime()->Unit(benchmark::kMillisecond);

/// The exact evaluation's dense steps at n = 1000 (a random SPD matrix, a factor R of rank n), each
/// as one single-threaded OpenBLAS call and as the tiles that run on the workers (core/tiled_*.h),
/// same run; counters in ms per call and the ratio single / tiled (on 2 cores at most 2). Also the
/// Gram's factor (gram_factor: its eigen-decomposition, once per placement), in ms and in
/// evaluations' dense steps (tiled).
void BM_TiledSteps(benchmark::State& state) {
  using namespace matlas::blas;
  const int n = static_cast<int>(state.range(0));
  const Library& lib = openblas();
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd K = a * a.transpose() / n + Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd R = Eigen::MatrixXd::Random(n, n);
  Eigen::MatrixXd L, W(n, n), Kinv(n, n), B(n, n), G(n, n);
  double single[3] = {}, tiled[3] = {}, factor = 0;
  const auto time = [](double& total, const auto& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  int info = 0;
  for (auto _ : state) {
    time(single[0], [&] { L = K; lib.dpotrf("L", &n, L.data(), &n, &info); });
    time(tiled[0], [&] { L = K; info = tiled_cholesky(n, L.data(), n); });
    time(single[1], [&] { Kinv = L; inverse_from_cholesky(n, Kinv.data(), n); });
    time(tiled[1], [&] { tiled_inverse_from_cholesky(n, L.data(), n, W.data(), Kinv.data(), n); });
    time(single[2], [&] {
      lib.dsymm(CblasColMajor, CblasLeft, CblasLower, n, n, 1.0, Kinv.data(), n, R.data(), n, 0.0, B.data(), n);
      lib.dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n, n, 1.0, B.data(), n, 0.0, G.data(), n);
    });
    time(tiled[2], [&] {
      tiled_product(n, n, n, 1.0, Kinv.data(), n, R.data(), n, B.data(), n);
      tiled_lower_gram(n, n, 1.0, B.data(), n, 0.0, G.data(), n);
    });
    time(factor, [&] { benchmark::DoNotOptimize(gram_factor(K)); });
  }
  const double calls = static_cast<double>(state.iterations());
  const char* names[3] = {"cholesky", "inverse", "products"};
  for (int k = 0; k < 3; ++k) {
    state.counters[std::string(names[k]) + "_single_ms"] = single[k] / calls * 1e3;
    state.counters[std::string(names[k]) + "_tiled_ms"] = tiled[k] / calls * 1e3;
    state.counters[std::string(names[k]) + "_ratio"] = single[k] / tiled[k];
  }
  state.counters["gram_factor_ms"] = factor / calls * 1e3;
  state.counters["gram_factor_in_evaluations"] = factor / (tiled[0] + tiled[1] + tiled[2]);
}
BENCHMARK(BM_TiledSteps)->Arg(1000)->Iterations(10)->UseRealTime()->Unit(benchmark::kMillisecond);

/// A real build's problem: MATLAS_BENCH_GRAM names a file of n x n doubles (a model's
/// layout_gram tensor), MATLAS_BENCH_LATENT one of n x q doubles (its latent points, row-major);
/// evaluated with the default priors of `matlas build` (LatentPrior::spread) at those points.
/// Skipped when the variables are not set.
Eigen::MatrixXd read_doubles(const char* path, Eigen::Index rows) {
  std::FILE* f = std::fopen(path, "rb");
  if (!f) return {};
  std::vector<double> v;
  for (double x; std::fread(&x, sizeof x, 1, f) == 1;) v.push_back(x);
  std::fclose(f);
  const Eigen::Index n = rows > 0 ? rows : static_cast<Eigen::Index>(std::lround(std::sqrt(v.size())));
  if (n == 0 || v.size() % static_cast<std::size_t>(n) != 0) return {};
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(v.data(), n, static_cast<Eigen::Index>(v.size()) / n);
}

void BM_EvaluationOfABuild(benchmark::State& state) {
  const char* gram_path = std::getenv("MATLAS_BENCH_GRAM");
  const char* latent_path = std::getenv("MATLAS_BENCH_LATENT");
  if (!gram_path || !latent_path) {
    state.SkipWithError("set MATLAS_BENCH_GRAM and MATLAS_BENCH_LATENT");
    return;
  }
  LikelihoodProblem p;
  p.gram = read_doubles(gram_path, 0);
  p.columns = kMerlColumns;
  p.prior = LatentPrior::spread();
  const Eigen::MatrixXd X = read_doubles(latent_path, p.gram.rows());
  if (p.gram.size() == 0 || X.size() == 0) {
    state.SkipWithError("cannot read MATLAS_BENCH_GRAM / MATLAS_BENCH_LATENT");
    return;
  }
  LikelihoodEvaluator evaluator(p);
  Eigen::MatrixXd G;
  for (auto _ : state) benchmark::DoNotOptimize(evaluator.normalized(X, &G));
  state.SetLabel("n = " + std::to_string(X.rows()) + ", q = " + std::to_string(X.cols()));
}
BENCHMARK(BM_EvaluationOfABuild)->Unit(benchmark::kMicrosecond);

void BM_Optimizers(benchmark::State& state) {
  const int q = static_cast<int>(state.range(0));
  const Eigen::MatrixXd X0 = pca_initialization(problem(), q);
  for (auto _ : state) {
    OptimizeOptions hj_options;
    hj_options.method = Optimizer::hooke_jeeves;
    hj_options.tolerance = env_or("MATLAS_BENCH_HJ_TOL", 1e-7);
    hj_options.max_iterations = 1000000;
    hj_options.time_limit_seconds = env_or("MATLAS_BENCH_HJ_MAX_SECONDS", 0);
    const OptimizeResult hj = optimize_latent(problem(), X0, hj_options, matlas::null_progress());

    // L-BFGS from the same start until it reaches HJ's final L (or converges below it: the
    // likelihood is multimodal and the two methods can end in different basins) ...
    OptimizeOptions to_target;
    to_target.target_value = hj.value;
    to_target.max_iterations = 100000;
    to_target.tolerance = 1e-9;
    const OptimizeResult lbfgs = optimize_latent(problem(), X0, to_target, matlas::null_progress());
    // ... and with 5 scaled starts (OptimizeOptions::starts), stopping at HJ's L.
    to_target.starts = 5;
    const OptimizeResult multi = optimize_latent(problem(), X0, to_target, matlas::null_progress());
    // L-BFGS to its own convergence (single start, no target).
    OptimizeOptions full;
    full.tolerance = 1e-9;
    full.max_iterations = 100000;
    const OptimizeResult converged = optimize_latent(problem(), X0, full, matlas::null_progress());

    state.counters["L0_per_col"] = hj.history.front() / kMerlColumns;
    state.counters["hj_s"] = hj.seconds;
    state.counters["hj_evals"] = hj.evaluations;
    state.counters["hj_L_per_col"] = hj.value / kMerlColumns;
    state.counters["lbfgs1_s"] = lbfgs.seconds;
    state.counters["lbfgs1_reached"] = lbfgs.value >= hj.value ? 1 : 0;
    state.counters["lbfgs1_over_hj"] = lbfgs.seconds / hj.seconds;
    state.counters["lbfgs5_s"] = multi.seconds;
    state.counters["lbfgs5_reached"] = multi.value >= hj.value ? 1 : 0;
    state.counters["lbfgs5_over_hj"] = multi.seconds / hj.seconds;
    state.counters["lbfgs5_evals"] = multi.evaluations;
    state.counters["lbfgs_full_s"] = converged.seconds;
    state.counters["lbfgs_full_L_per_col"] = converged.value / kMerlColumns;
    state.SetLabel("hj: " + hj.stop_reason + "; lbfgs 1 start: " + lbfgs.stop_reason + "; 5 starts: " + multi.stop_reason);
  }
}
BENCHMARK(BM_Optimizers)->Arg(2)->Arg(5)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
