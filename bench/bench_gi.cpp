// GI image composition: a 512x512 GI image from a basis of n = 100 materials (101 images with the
// mean table's), float32 and float16, dense weights (every image read), against a plain parallel read of the
// same number of bytes in the same run (BM_GiStreamSameBytes, registered first). The images are
// synthetic: the composition's cost does not depend on their content. Then the default (convex)
// weights at 512 x 512, and the scene view's composition (192 x 144, convex weights).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "atlas/gi_basis.h"
#include "core/parallel.h"
#include "core/simd_clones.h"

namespace {

using matlas::Image;
using matlas::atlas::GiBasis;

constexpr int kSize = 512, kCount = 100;
constexpr std::size_t kValues = static_cast<std::size_t>(kSize) * kSize * 3;
constexpr std::size_t kBytes = (kCount + 1) * kValues * sizeof(float);

const GiBasis& basis() {
  static const GiBasis b = [] {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Image p(kSize, kSize);
    std::vector<Image> images(kCount + 1, Image(kSize, kSize));
    for (Image& im : images)
      for (float& v : im.rgb) v = u(rng);
    std::vector<std::string> names(kCount, "m");
    return GiBasis(p, images, images, names, {});
  }();
  return b;
}

/// Wrapping integer sum of 32-bit words: associative, so it vectorises (unlike a float sum
/// without -ffast-math), and the read is limited by memory alone.
MATLAS_SIMD_CLONES std::uint32_t word_sum(const std::uint32_t* p, std::size_t n) {
  std::uint32_t s = 0;
  for (std::size_t i = 0; i < n; ++i) s += p[i];
  return s;
}

void BM_GiStreamSameBytes(benchmark::State& state) {
  const std::vector<std::uint32_t> data(kBytes / sizeof(std::uint32_t), 1u);
  const std::size_t blocks = data.size() / 8192;
  std::vector<std::uint32_t> partial(blocks);
  for (auto _ : state) {
    matlas::parallel_for(0, blocks, [&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b) partial[b] = word_sum(data.data() + b * 8192, 8192);
    });
    benchmark::DoNotOptimize(partial.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(kBytes));
}
BENCHMARK(BM_GiStreamSameBytes)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GiCompose512n100(benchmark::State& state) {
  const GiBasis& b = basis();
  Eigen::VectorXd w = Eigen::VectorXd::Constant(kCount, 0.5 / kCount);  // dense: every image read
  Image out(kSize, kSize);
  for (auto _ : state) {
    b.compose(w, GiBasis::Part::all, out.rgb.data());
    benchmark::DoNotOptimize(out.rgb.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(kBytes));
}
BENCHMARK(BM_GiCompose512n100)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GiCompose512n100Half(benchmark::State& state) {
  static GiBasis b = [] {
    GiBasis copy = basis();
    copy.convert_to_half();
    return copy;
  }();
  Eigen::VectorXd w = Eigen::VectorXd::Constant(kCount, 0.5 / kCount);
  Image out(kSize, kSize);
  for (auto _ : state) {
    b.compose(w, GiBasis::Part::all, out.rgb.data());
    benchmark::DoNotOptimize(out.rgb.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(kBytes / 2));
}
BENCHMARK(BM_GiCompose512n100Half)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The default (convex) interpolation at 512 x 512: weights on k materials. On the 83 realistic
/// materials' q = 2 map, 2000 random points of the latent box have a median of 5 non-zero convex
/// weights, 8 at the 90th percentile and 15 at most.
void BM_GiCompose512n100Convex(benchmark::State& state) {
  const GiBasis& b = basis();
  const auto k = static_cast<int>(state.range(0));
  Eigen::VectorXd w = Eigen::VectorXd::Zero(kCount);
  for (int i = 0; i < k; ++i) w[(i * 37) % kCount] = 1.0 / k;
  Image out(kSize, kSize);
  for (auto _ : state) {
    b.compose(w, GiBasis::Part::all, out.rgb.data());
    benchmark::DoNotOptimize(out.rgb.data());
  }
}
BENCHMARK(BM_GiCompose512n100Convex)->Arg(5)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The browser's scene view: a 192 x 144 image (the server's default size for scenes traced on
/// demand), n = 100, convex weights of 3 materials (what the default interpolation gives).
void BM_GiComposeSceneView192x144Convex(benchmark::State& state) {
  static const GiBasis b = [] {
    Image p(192, 144);
    std::vector<Image> images(kCount + 1, Image(192, 144));
    for (std::size_t k = 0; k < images.size(); ++k)
      for (std::size_t v = 0; v < images[k].rgb.size(); ++v) images[k].rgb[v] = static_cast<float>((k + v) % 7);
    return GiBasis(p, images, images, std::vector<std::string>(kCount, "m"), {});
  }();
  Eigen::VectorXd w = Eigen::VectorXd::Zero(kCount);
  w[10] = 0.5;
  w[41] = 0.3;
  w[77] = 0.2;
  Image out(192, 144);
  for (auto _ : state) {
    b.compose(w, GiBasis::Part::all, out.rgb.data());
    benchmark::DoNotOptimize(out.rgb.data());
  }
}
BENCHMARK(BM_GiComposeSceneView192x144Convex)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
