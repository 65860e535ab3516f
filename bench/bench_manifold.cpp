// Manifold build and query benchmarks on the 100-material database (bench/make_bench_db.sh),
// each reported as a ratio to a physical limit measured in the same run:
//   - the build's pass over the files vs reading the same files raw from the page cache, and vs
//     raw reading plus the Gram computation alone; its file-reading step vs the raw read;
//   - the Gram update (add_gram_upper) vs the machine's dense matrix-product (dgemm, all cores);
//   - dsyrk on narrow slices vs the widest (the pass's Gram slices);
//   - the whole table at x vs one streaming read of the stored data;
//   - one value at x once w(x) is known (absolute, ns);
//   - the two Gram matrices of a large build alone (BM_GramsAlone: the floor of bench/e2e_1000.sh).
// Set MATLAS_BENCH_DB to the database folder (default /tmp/matlas-bench-db).
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <random>
#include <thread>
#include <unistd.h>

#include <benchmark/benchmark.h>
#include "core/blas.h"

#include "core/parallel.h"
#include "manifold/build.h"
#include "manifold/column_blocks.h"
#include "manifold/gram.h"
#include "manifold/gram_update.h"
#include "manifold/model.h"

namespace fs = std::filesystem;
using namespace matlas;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

fs::path database() {
  const char* env = std::getenv("MATLAS_BENCH_DB");
  return env ? fs::path(env) : fs::path("/tmp/matlas-bench-db");
}

bool have_database(benchmark::State& state) {
  if (fs::is_directory(database())) return true;
  state.SkipWithError("no benchmark database: run bench/make_bench_db.sh (or set MATLAS_BENCH_DB)");
  return false;
}

/// Reads every .binary file of the set raw into one reused 1 MiB buffer per thread (it stays in
/// cache, so this is the fastest way to read), on `threads` threads each taking every
/// threads-th file; returns bytes read.
std::size_t raw_read(const MaterialSet& set, unsigned threads = 1) {
  std::vector<std::size_t> totals(threads, 0);
  const auto read_files = [&](unsigned t) {
    std::vector<char> buffer(1 << 20);
    for (std::size_t i = t; i < set.size(); i += threads) {
      const int fd = ::open(set.file(i).path().c_str(), O_RDONLY);
      ssize_t got;
      while ((got = ::read(fd, buffer.data(), buffer.size())) > 0) totals[t] += static_cast<std::size_t>(got);
      ::close(fd);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(read_files, t);
  read_files(0);
  for (std::thread& th : pool) th.join();
  std::size_t total = 0;
  for (std::size_t b : totals) total += b;
  return total;
}

/// Seconds of add_gram_upper for `blocks` blocks of n x 32768 (the pass's Gram work alone).
double gram_only_seconds(int n, double blocks, int grams) {
  BlockMatrix a = BlockMatrix::Random(n, 32768);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n, n);
  add_gram_upper(a, s);  // warm-up
  const double t0 = now();
  for (int r = 0; r < 8; ++r) add_gram_upper(a, s);
  return (now() - t0) / 8.0 * blocks * grams;
}

/// The build's pass over the files (default layout: two Gram matrices; the data written as it
/// goes) against the floors measured in the same run: reading the files raw (one thread, and all
/// cores), and the Gram computation alone on as many columns as the pass keeps.
///   ratio_to_raw      pass / raw read (one thread)
///   ratio_to_floor    pass / (raw read + Grams alone): what the pass adds to its unavoidable work
///   files_vs_raw      the pass's file-reading step (copy, hash, NaN check, scaling, column sums,
///                     on all cores) / raw read on one thread; files_vs_raw_all_cores the same
///                     against a raw read on all cores
///   products_vs_gram  the pass's Gram step (both Grams, albedo curves, data output) / Grams alone
void BM_BuildPassVsRawRead(benchmark::State& state) {
  if (!have_database(state)) return;
  const MaterialSet set = MaterialSet::open({database()});
  raw_read(set);  // warm the page cache
  const fs::path out = fs::temp_directory_path() / "matlas-bench-pass.matlas";
  double raw = 0, raw_all = 0, pass = 0, grams = 0;
  PassSteps steps;
  std::size_t bytes = 0;
  BuildOptions o;
  o.dim = 5;
  for (auto _ : state) {
    double t0 = now();
    bytes = raw_read(set);
    raw += now() - t0;
    t0 = now();
    raw_read(set, worker_count());
    raw_all += now() - t0;
    const BuildReport r = build_model(set, o, out);
    pass += r.pass_seconds;
    steps.read += r.pass_steps.read;
    steps.sweep += r.pass_steps.sweep;
    steps.products += r.pass_steps.products;
    fs::remove(out);
    ::sync();  // let the freed blocks settle before the next round
    const double blocks = static_cast<double>(r.kept_columns) / 32768.0;  // the Grams cover kept columns
    grams += gram_only_seconds(static_cast<int>(set.size()), blocks, o.layout.is_identity() ? 1 : 2);
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["materials"] = static_cast<double>(set.size());
  state.counters["raw_GBps"] = static_cast<double>(bytes) / (raw / it) / 1e9;
  state.counters["pass_s"] = pass / it;
  state.counters["raw_read_s"] = raw / it;
  state.counters["raw_read_all_cores_s"] = raw_all / it;
  state.counters["gram_only_s"] = grams / it;
  state.counters["files_s"] = steps.read / it;
  state.counters["sweep_s"] = steps.sweep / it;
  state.counters["products_s"] = steps.products / it;
  state.counters["ratio_to_raw"] = pass / raw;
  state.counters["ratio_to_floor"] = pass / (raw + grams);
  state.counters["files_vs_raw"] = steps.read / raw;
  state.counters["files_vs_raw_all_cores"] = steps.read / raw_all;
  state.counters["products_vs_gram"] = steps.products / grams;
}
BENCHMARK(BM_BuildPassVsRawRead)->Unit(benchmark::kMillisecond)->Iterations(2)->UseRealTime();

/// The build's Gram update against the machine's dgemm (1024^3, OpenBLAS on all cores). The two
/// are timed in separate phases with a pause between: OpenBLAS's own threads keep spinning for
/// a while after a call and would otherwise steal the cores from the Gram's workers.
void BM_GramVsGemm(benchmark::State& state) {
  const int n = 100, k = 32768, g = 1024;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> d;
  BlockMatrix a(n, k);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = d(rng);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n, n);
  std::vector<double> x(static_cast<std::size_t>(g) * g), y(x.size()), z(x.size());
  for (double& v : x) v = d(rng);
  for (double& v : y) v = d(rng);
  double t_syrk = 0, t_gemm = 0;
  const auto pause = [] { std::this_thread::sleep_for(std::chrono::milliseconds(300)); };
  for (auto _ : state) {
    double t0 = now();
    for (int r = 0; r < 3; ++r)
      matlas::blas::openblas().dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, g, g, g, 1.0, x.data(), g, y.data(), g, 0.0, z.data(), g);
    t_gemm += (now() - t0) / 3;
    pause();
    t0 = now();
    for (int r = 0; r < 10; ++r) add_gram_upper(a, s);  // the build's Gram update
    t_syrk += now() - t0;
    pause();
  }
  const double it = static_cast<double>(state.iterations());
  const double syrk_flops = 10.0 * n * (n + 1.0) * k;  // n(n+1)/2 dot products of length k, 2 flops each
  const double gemm_flops = 2.0 * g * g * g;
  state.counters["gram_GFLOPs"] = syrk_flops / (t_syrk / it) / 1e9;
  state.counters["gemm_GFLOPs"] = gemm_flops / (t_gemm / it) / 1e9;
  state.counters["ratio_to_gemm"] = (syrk_flops / t_syrk) / (gemm_flops / t_gemm);
}
BENCHMARK(BM_GramVsGemm)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

/// The floor of a large build's products (bench/e2e_1000.sh): the two Gram matrices of the default
/// layout alone, as the pass computes them (the linear one in double, the placement one in single
/// precision, slices of GramAccumulator on all cores), on random n x 4096 blocks, scaled to the
/// pass's kept columns. MATLAS_BENCH_N (default 1000) materials, MATLAS_BENCH_COLUMNS (default
/// 3,888,000) kept columns; gram_only_s is the time of the whole pass's Grams, cpu_s its CPU time.
void BM_GramsAlone(benchmark::State& state) {
  const char* n_env = std::getenv("MATLAS_BENCH_N");
  const char* c_env = std::getenv("MATLAS_BENCH_COLUMNS");
  const Eigen::Index n = n_env ? std::atol(n_env) : 1000;
  const double columns = c_env ? std::atof(c_env) : 3888000.0;
  const std::size_t k = 4096, slices = GramAccumulator::slices(k);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> d;
  BlockMatrix a(n, static_cast<Eigen::Index>(k));
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = d(rng);
  const std::vector<float> af(a.data(), a.data() + a.size());
  GramAccumulator linear(n, k), layout(n, k);
  const auto block = [&] {
    parallel_for_each(0, 2 * slices, [&](std::size_t s) {
      if (s < slices)
        linear.add_slice(a.data(), k, k, s);
      else
        layout.add_slice(af.data(), k, k, s - slices);
    });
  };
  block();  // warm-up
  constexpr int kBlocks = 4;
  double wall = 0, cpu = 0;
  for (auto _ : state) {
    const std::clock_t c0 = std::clock();
    const double t0 = now();
    for (int b = 0; b < kBlocks; ++b) block();
    wall += now() - t0;
    cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  }
  const double scale = columns / (static_cast<double>(k) * kBlocks * static_cast<double>(state.iterations()));
  state.counters["materials"] = static_cast<double>(n);
  state.counters["columns"] = columns;
  state.counters["gram_only_s"] = wall * scale;
  state.counters["cpu_s"] = cpu * scale;
}
BENCHMARK(BM_GramsAlone)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

/// Single-threaded dsyrk slices of a row-major n x 4096 block (as GramAccumulator::add_slice
/// calls it), for slice widths 512 .. 4096: GFLOP/s of the useful n(n+1)k flops, and the ratio to the
/// 4096-column slice measured in the same run (why the pass can use narrow slices).
void BM_GramSliceWidth(benchmark::State& state) {
  const int n = 100;
  const std::size_t width = static_cast<std::size_t>(state.range(0)), k = 4096;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> d;
  BlockMatrix a(n, static_cast<Eigen::Index>(k));
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = d(rng);
  const auto seconds_per_flop = [&](std::size_t w) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
    const std::size_t slices = k / w, reps = 64;
    const double t0 = now();
    for (std::size_t r = 0; r < reps; ++r)
      for (std::size_t s = 0; s < slices; ++s)
        matlas::blas::openblas().dsyrk(CblasColMajor, CblasUpper, CblasTrans, n, static_cast<int>(w), 1.0, a.data() + s * w,
                    static_cast<int>(k), 1.0, c.data(), n);
    return (now() - t0) / (static_cast<double>(reps) * n * (n + 1.0) * static_cast<double>(k));
  };
  double t_width = 0, t_full = 0;
  for (auto _ : state) {
    t_width += seconds_per_flop(width);
    t_full += seconds_per_flop(k);
  }
  state.counters["GFLOPs"] = 1e-9 / (t_width / static_cast<double>(state.iterations()));
  state.counters["ratio_to_4096"] = t_full / t_width;
}
BENCHMARK(BM_GramSliceWidth)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Iterations(3)->UseRealTime();

/// GramAccumulator::add_slice on a row-major 100 x 4096 block in double (dsyrk) and in single
/// precision (ssyrk into a scratch, added to the double accumulator: the layout Gram's path),
/// same run: GFLOP/s of the n(n+1)k useful flops each and the single / double speed ratio.
void BM_GramSliceSingleVsDouble(benchmark::State& state) {
  const int n = 100;
  const std::size_t k = 4096, slices = matlas::GramAccumulator::slices(k), reps = 32;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> d;
  BlockMatrix a(n, static_cast<Eigen::Index>(k));
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = d(rng);
  const std::vector<float> af(a.data(), a.data() + a.size());
  double t_double = 0, t_single = 0;
  for (auto _ : state) {
    matlas::GramAccumulator g_double(n, k), g_single(n, k);
    double t0 = now();
    for (std::size_t r = 0; r < reps; ++r)
      for (std::size_t s = 0; s < slices; ++s) g_double.add_slice(a.data(), k, k, s);
    t_double += now() - t0;
    t0 = now();
    for (std::size_t r = 0; r < reps; ++r)
      for (std::size_t s = 0; s < slices; ++s) g_single.add_slice(af.data(), k, k, s);
    t_single += now() - t0;
    benchmark::DoNotOptimize(g_single.total().data());
  }
  const double flops = static_cast<double>(state.iterations()) * reps * n * (n + 1.0) * static_cast<double>(k);
  state.counters["double_GFLOPs"] = flops / t_double / 1e9;
  state.counters["single_GFLOPs"] = flops / t_single / 1e9;
  state.counters["single_over_double_speed"] = t_double / t_single;
}
BENCHMARK(BM_GramSliceSingleVsDouble)->Iterations(3)->UseRealTime();

/// The cost of the compensated sum (gram_update.h: each slice's product into a scratch, then
/// added with TwoSum, so that a pass split across processes gives the same bits) against dsyrk
/// accumulating straight into the sum (beta = 1, no compensation), one thread, same run, on a
/// row-major n x 4096 block: the time ratio compensated / plain for n = 100 and n = 1000.
void BM_GramCompensationCost(benchmark::State& state) {
  const auto n = static_cast<int>(state.range(0));
  const std::size_t k = 4096, slices = matlas::GramAccumulator::slices(k);
  const std::size_t reps = n >= 1000 ? 1 : 32;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> d;
  BlockMatrix a(n, static_cast<Eigen::Index>(k));
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = d(rng);
  double t_plain = 0, t_compensated = 0;
  for (auto _ : state) {
    Eigen::MatrixXd plain = Eigen::MatrixXd::Zero(n, n);
    double t0 = now();
    for (std::size_t r = 0; r < reps; ++r)
      for (std::size_t s = 0; s < slices; ++s)
        matlas::blas::openblas().dsyrk(CblasColMajor, CblasUpper, CblasTrans, n,
                                       static_cast<int>(matlas::GramAccumulator::kSlice), 1.0,
                                       a.data() + s * matlas::GramAccumulator::kSlice, static_cast<int>(k), 1.0,
                                       plain.data(), n);
    t_plain += now() - t0;
    matlas::GramAccumulator compensated(n, k);
    t0 = now();
    for (std::size_t r = 0; r < reps; ++r)
      for (std::size_t s = 0; s < slices; ++s) compensated.add_slice(a.data(), k, k, s);
    t_compensated += now() - t0;
    benchmark::DoNotOptimize(plain.data());
    benchmark::DoNotOptimize(compensated.total().data());
  }
  state.counters["plain_s"] = t_plain / static_cast<double>(state.iterations());
  state.counters["compensated_over_plain"] = t_compensated / t_plain;
}
BENCHMARK(BM_GramCompensationCost)->Arg(100)->Arg(1000)->Iterations(3)->UseRealTime();

const Model* bench_model() {
  static std::unique_ptr<Model> model;
  if (!model) {
    const fs::path path = fs::temp_directory_path() / "matlas-bench-q5.matlas";
    if (!fs::exists(path)) {
      BuildOptions o;
      o.dim = 5;
      build_model(MaterialSet::open({database()}), o, path);
    }
    model = std::make_unique<Model>(Model::open(path));
  }
  return model.get();
}

void BM_TableAtXVsStreamingRead(benchmark::State& state) {
  if (!have_database(state)) return;
  const Model& m = *bench_model();
  const Eigen::VectorXd w = m.weights(0.5 * (m.latent().row(0) + m.latent().row(1)).transpose());
  const std::size_t floats = m.kept_columns() * static_cast<std::size_t>(m.count());
  double t_table = 0, t_read = 0;
  bool warm = false;
  for (auto _ : state) {
    if (!warm) {  // fault the mapping in (a fresh build wrote it past the page cache)
      for (int r = 0; r < 2; ++r) {
        const BrdfTable warmup = m.table(w);
        benchmark::DoNotOptimize(warmup.stored().data());
      }
      warm = true;
    }
    double t0 = now();
    std::vector<double> partial(worker_count(), 0.0);
    parallel_for(0, worker_count(), [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t) {
        const std::size_t a = floats * t / worker_count(), b = floats * (t + 1) / worker_count();
        const float* p = m.data_f32(0);
        float s0 = 0, s1 = 0, s2 = 0, s3 = 0;
        std::size_t i = a;
        for (; i + 4 <= b; i += 4) {
          s0 += p[i];
          s1 += p[i + 1];
          s2 += p[i + 2];
          s3 += p[i + 3];
        }
        partial[t] = s0 + s1 + s2 + s3;
      }
    });
    benchmark::DoNotOptimize(partial.data());
    t_read += now() - t0;
    t0 = now();
    const BrdfTable table = m.table(w);
    benchmark::DoNotOptimize(table.stored().data());
    t_table += now() - t0;
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["materials"] = m.count();
  state.counters["data_GB"] = static_cast<double>(floats) * 4 / 1e9;
  state.counters["read_GBps"] = static_cast<double>(floats) * 4 / (t_read / it) / 1e9;
  state.counters["table_s"] = t_table / it;
  state.counters["ratio_to_read"] = t_table / t_read;
}
BENCHMARK(BM_TableAtXVsStreamingRead)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void BM_ValueAtX(benchmark::State& state) {
  if (!have_database(state)) return;
  const Model& m = *bench_model();
  const Eigen::VectorXd w = m.weights(m.latent().colwise().mean().transpose());
  std::mt19937_64 rng(3);
  std::vector<std::size_t> indices(4096);
  std::size_t found = 0;
  while (found < indices.size()) {
    const std::size_t v = rng() % (3 * m.dims().bins());
    if (m.kept(v)) indices[found++] = v;
  }
  // Touch the data once so the benchmark measures the query, not page faults.
  for (std::size_t v : indices) benchmark::DoNotOptimize(m.value(v, w));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.value(indices[i++ & 4095], w));
  }
  state.counters["materials"] = m.count();
}
BENCHMARK(BM_ValueAtX);

}  // namespace

BENCHMARK_MAIN();
