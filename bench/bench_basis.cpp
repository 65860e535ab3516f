// Image-basis composition (the instant preview): a 512x512 image from n = 100 material images,
// in float32, float16 (F16C when available), a low-rank form and float16 with convex weights on
// k materials (only their images read), against the machine's measured
// memory read bandwidth (baseline in the same run: BM_MemoryReadBandwidth is registered first).
//
// The basis is synthetic but shaped like a rendered one: the object (a disc) covers ~60% of the
// pixels; every material image is a smooth combination of 12 patterns with 0.2% independent noise (real
// bases have no independent noise: all materials share their samples, so their rank is lower).
#include <benchmark/benchmark.h>

#include <atomic>
#include <cmath>
#include <random>
#include <vector>

#include "core/parallel.h"
#include "render/image_basis.h"

namespace {

using matlas::Image;
using matlas::render::ImageBasis;

constexpr int kSize = 512, kCount = 100;

std::vector<ImageBasis> make_bases() {
  std::mt19937 rng(5);
  std::normal_distribution<float> gauss;
  std::vector<Image> patterns;
  for (int k = 0; k < 12; ++k) {
    Image p(kSize, kSize);
    const float fx = 1.0f + static_cast<float>(k % 4), fy = 1.0f + static_cast<float>(k / 4);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int c = 0; c < 3; ++c)
          p.pixel(x, y)[c] = 0.5f + 0.5f * std::sin(fx * static_cast<float>(x) / 40.0f + static_cast<float>(c)) *
                                        std::cos(fy * static_cast<float>(y) / 50.0f);
    patterns.push_back(std::move(p));
  }
  std::vector<Image> images;
  // The mean summed in double: where every image has the background's 0.3 so has the mean, as in
  // a rendered basis (those pixels are not active).
  std::vector<double> mean_sum(static_cast<std::size_t>(kSize) * kSize * 3, 0.0);
  for (int i = 0; i < kCount; ++i) {
    Image im(kSize, kSize);
    std::fill(im.rgb.begin(), im.rgb.end(), 0.3f);
    float coeff[12];
    for (float& a : coeff) a = std::abs(gauss(rng)) * 0.2f;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const float dx = static_cast<float>(x) - kSize / 2.0f, dy = static_cast<float>(y) - kSize / 2.0f;
        if (dx * dx + dy * dy > 0.19f * kSize * kSize) continue;
        for (int c = 0; c < 3; ++c) {
          float v = 0;
          for (int k = 0; k < 12; ++k) v += coeff[k] * patterns[static_cast<std::size_t>(k)].pixel(x, y)[c];
          im.pixel(x, y)[c] = v * (1.0f + 0.002f * gauss(rng));
        }
      }
    for (std::size_t k = 0; k < mean_sum.size(); ++k) mean_sum[k] += im.rgb[k];
    images.push_back(std::move(im));
  }
  Image mean(kSize, kSize);
  for (std::size_t k = 0; k < mean_sum.size(); ++k) mean.rgb[k] = static_cast<float>(mean_sum[k] / kCount);
  std::vector<ImageBasis> bases;
  bases.emplace_back(mean, images);
  bases.push_back(bases[0]);
  bases[1].convert_to_half();
  bases.push_back(bases[0]);
  bases[2].compress(1e-2);
  return bases;
}

const ImageBasis& basis(int which) {
  static const std::vector<ImageBasis> bases = make_bases();
  return bases[static_cast<std::size_t>(which)];
}

void BM_MemoryReadBandwidth(benchmark::State& state) {
  const std::size_t count = std::size_t(1) << 26;  // 256 MiB of floats
  std::vector<float> data(count, 1.0f);
  for (auto _ : state) {
    std::atomic<double> total{0};
    matlas::parallel_for(0, count / 4096, [&](std::size_t b0, std::size_t b1) {
      float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (std::size_t i = b0 * 4096; i < b1 * 4096; i += 8)
        for (int k = 0; k < 8; ++k) acc[k] += data[i + static_cast<std::size_t>(k)];
      double s = 0;
      for (float a : acc) s += a;
      double cur = total.load();
      while (!total.compare_exchange_weak(cur, cur + s)) {}
    });
    benchmark::DoNotOptimize(total.load());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * count * sizeof(float)));
  state.counters["GB/s"] = benchmark::Counter(static_cast<double>(count * sizeof(float)) * 1e-9,
                                              benchmark::Counter::kIsIterationInvariantRate);
}

void compose(benchmark::State& state, int which, bool low_rank) {
  const ImageBasis& b = basis(which);
  Eigen::VectorXd w = Eigen::VectorXd::Constant(kCount, 0.5 / kCount);
  w[3] += 0.3;
  w[40] += 0.2;
  std::vector<float> out(static_cast<std::size_t>(kSize) * kSize * 3);
  for (auto _ : state) {
    if (low_rank) b.compose_low_rank(w, out.data());
    else b.compose(w, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  const double bytes = low_rank ? static_cast<double>(b.low_rank()) / kCount * static_cast<double>(basis(0).compose_bytes())
                                : static_cast<double>(b.compose_bytes());
  state.counters["MB_read"] = bytes * 1e-6;
  state.counters["GB/s"] = benchmark::Counter(bytes * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["active"] = b.active_fraction();
  if (low_rank) {
    state.counters["rank"] = b.low_rank();
    state.counters["rel_error"] = b.low_rank_report().relative_error;
  }
}

/// Convex weights on k materials (what the default interpolation gives: a handful): only their
/// images are read, the bytes counted accordingly. Through compose_fast of the low-rank basis
/// (the drag previews' call) with k <= rank, the same exact composition (in float32).
void convex(benchmark::State& state, int which, bool low_rank) {
  const ImageBasis& b = basis(which);
  const auto k = static_cast<int>(state.range(0));
  Eigen::VectorXd w = Eigen::VectorXd::Zero(kCount);
  for (int j = 0; j < k; ++j) w[(7 * j + 3) % kCount] = 1.0 / k;
  std::vector<float> out(static_cast<std::size_t>(kSize) * kSize * 3);
  for (auto _ : state) {
    if (low_rank) b.compose_fast(w, out.data());
    else b.compose(w, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  const double bytes = static_cast<double>(k) / kCount * static_cast<double>(b.compose_bytes());
  state.counters["MB_read"] = bytes * 1e-6;
  state.counters["GB/s"] = benchmark::Counter(bytes * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ComposeF16Convex(benchmark::State& state) { convex(state, 1, false); }
void BM_ComposeLowRankConvex(benchmark::State& state) { convex(state, 2, true); }
void BM_ComposeF32(benchmark::State& state) { compose(state, 0, false); }
void BM_ComposeF16(benchmark::State& state) { compose(state, 1, false); }
void BM_ComposeLowRank(benchmark::State& state) { compose(state, 2, true); }

}  // namespace

BENCHMARK(BM_MemoryReadBandwidth)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ComposeF32)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ComposeF16)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ComposeLowRank)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ComposeF16Convex)->Arg(5)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ComposeLowRankConvex)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
