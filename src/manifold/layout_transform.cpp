#include "manifold/layout_transform.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "core/simd_clones.h"

namespace matlas {

std::string LayoutTransform::to_string() const {
  const char* map_name = map == Map::linear ? "linear" : map == Map::cube_root ? "cbrt" : "log";
  return cosine_weighted ? std::string("cosine-") + map_name : std::string(map_name);
}

LayoutTransform LayoutTransform::parse(const std::string& name) {
  LayoutTransform t;
  std::string rest = name;
  if (rest.rfind("cosine-", 0) == 0) {
    t.cosine_weighted = true;
    rest = rest.substr(7);
  } else if (rest == "cosine") {
    t.cosine_weighted = true;
    rest = "linear";
  }
  if (rest == "linear") t.map = Map::linear;
  else if (rest == "cbrt") t.map = Map::cube_root;
  else if (rest == "log") t.map = Map::log;
  else
    throw Error("unknown layout transform '" + name +
                "' (expected linear, cbrt or log, optionally prefixed with cosine-)");
  return t;
}

namespace {

/// Cube root to float precision (about 1e-7 relative), free of branches, divisions and 64-bit
/// integer arithmetic, so that the loops below vectorise (16 floats per AVX-512 register): the
/// inverse cube root a^(-1/3) is guessed from the bits of a (within 14 %), refined by four
/// Newton steps y <- y (4 - a y^3) / 3 (quadratic convergence: 14 % -> 4 % -> 3e-3 -> 2e-5 ->
/// rounding), and cbrt(a) = a y^2. Magnitudes below 1e-30 (far below any measured reflectance)
/// come out below 1e-18 instead of their exact root. Only used to place latent points.
inline float fast_cbrt(float x) {
  const float a = std::abs(x);
  constexpr std::uint32_t kTiny = 0x0DA24260u;  // the bits of 1e-30f
  const std::uint32_t bits = std::max(std::bit_cast<std::uint32_t>(a), kTiny);
  const float guess = std::bit_cast<float>(0x548C2B4Bu - bits / 3u);
  const auto newton = [a](float y) { return y * (4.0f - a * y * y * y) * (1.0f / 3.0f); };
  const float y = newton(newton(newton(newton(guess))));
  return std::copysign(a * y * y, x);
}

/// One row's run of a block, each value read once: centred[t] = in[t] - mean[t], out[t] =
/// float(cbrt(in[t])) * weight[t] (the transformed copy, not yet centred), sum[t] += out[t].
MATLAS_SIMD_CLONES void centre_cbrt_run(const double* __restrict in, const double* __restrict mean,
                                        const float* __restrict weight, double* __restrict centred,
                                        float* __restrict out, double* __restrict sum, std::size_t n) {
  for (std::size_t t = 0; t < n; ++t) {
    const double x = in[t];
    centred[t] = x - mean[t];
    const float y = fast_cbrt(static_cast<float>(x)) * weight[t];
    out[t] = y;
    sum[t] += y;
  }
}

MATLAS_SIMD_CLONES void centre_cbrt_run(const double* __restrict in, const double* __restrict mean,
                                        double* __restrict centred, float* __restrict out,
                                        double* __restrict sum, std::size_t n) {
  for (std::size_t t = 0; t < n; ++t) {
    const double x = in[t];
    centred[t] = x - mean[t];
    const float y = fast_cbrt(static_cast<float>(x));
    out[t] = y;
    sum[t] += y;
  }
}

/// The same for any map, row by row over the runs (the column sums in `sum`, indexed from the
/// first run's output column).
template <class Map>
void centre_map_runs(const BlockMatrix& values, std::span<const KeptRun> runs, const double* mean, double* centred,
                     Map map, const float* weight, float* out, double* sum, std::size_t ld) {
  const std::size_t first = runs.front().out;
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double* row = values.row(i).data();
    const std::size_t offset = static_cast<std::size_t>(i) * ld;
    for (const KeptRun& run : runs)
      for (std::size_t t = 0; t < run.count; ++t) {
        const double x = row[run.first + t];
        centred[offset + run.out + t] = x - mean[run.first + t];
        const auto y = static_cast<float>(map(x));
        const float v = weight ? y * weight[run.first + t] : y;
        out[offset + run.out + t] = v;
        sum[run.out + t - first] += v;
      }
  }
}

void centre_cbrt_runs(const BlockMatrix& values, std::span<const KeptRun> runs, const double* mean, double* centred,
                      const float* weight, float* out, double* sum, std::size_t ld) {
  const std::size_t first = runs.front().out;
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double* row = values.row(i).data();
    const std::size_t offset = static_cast<std::size_t>(i) * ld;
    for (const KeptRun& run : runs) {
      double* const c = centred + offset + run.out;
      float* const o = out + offset + run.out;
      double* const s = sum + (run.out - first);
      if (weight)
        centre_cbrt_run(row + run.first, mean + run.first, weight + run.first, c, o, s, run.count);
      else
        centre_cbrt_run(row + run.first, mean + run.first, c, o, s, run.count);
    }
  }
}

/// a[i, j] -= float(sum[j - first] / rows) for columns [first, first + count) of every row.
MATLAS_SIMD_CLONES void subtract_means(float* a, std::size_t rows, std::size_t ld, std::size_t first,
                                       const double* sum, std::size_t count) {
  std::vector<float> mean(count);
  const double inv = 1.0 / static_cast<double>(rows);
  for (std::size_t j = 0; j < count; ++j) mean[j] = static_cast<float>(sum[j] * inv);
  for (std::size_t i = 0; i < rows; ++i) {
    float* __restrict row = a + i * ld + first;
    const float* __restrict m = mean.data();
    for (std::size_t j = 0; j < count; ++j) row[j] -= m[j];
  }
}

}  // namespace

void centre_and_transform_kept(const BlockMatrix& values, std::span<const KeptRun> runs, const double* mean,
                               double* centred, const LayoutTransform& layout, const float* cosine,
                               float* transformed, std::size_t ld) {
  if (runs.empty()) return;
  const std::size_t first = runs.front().out, count = runs.back().out + runs.back().count - first;
  std::vector<double> sum(count, 0.0);  // the transformed columns' sums over the rows, in row order
  const float* weight = layout.cosine_weighted ? cosine : nullptr;
  switch (layout.map) {
    case LayoutTransform::Map::linear:
      centre_map_runs(values, runs, mean, centred, [](double x) { return x; }, weight, transformed, sum.data(), ld);
      break;
    case LayoutTransform::Map::cube_root:
      centre_cbrt_runs(values, runs, mean, centred, weight, transformed, sum.data(), ld);
      break;
    case LayoutTransform::Map::log:
      centre_map_runs(values, runs, mean, centred, [](double x) { return std::log1p(100.0 * std::max(x, 0.0)); },
                      weight, transformed, sum.data(), ld);
      break;
  }
  subtract_means(transformed, static_cast<std::size_t>(values.rows()), ld, first, sum.data(), count);
}

}  // namespace matlas
