#include "manifold/layout_transform.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

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

MATLAS_SIMD_CLONES void cbrt_run(const double* __restrict in, const float* __restrict weight,
                                 float* __restrict out, std::size_t n) {
  for (std::size_t t = 0; t < n; ++t) out[t] = fast_cbrt(static_cast<float>(in[t])) * weight[t];
}

MATLAS_SIMD_CLONES void cbrt_run(const double* __restrict in, float* __restrict out, std::size_t n) {
  for (std::size_t t = 0; t < n; ++t) out[t] = fast_cbrt(static_cast<float>(in[t]));
}

template <class Map>
void transform_runs(const BlockMatrix& values, std::span<const KeptRun> runs, Map map, const float* cosine,
                    float* out, std::size_t ld) {
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double* row = values.row(i).data();
    float* dst = out + static_cast<std::size_t>(i) * ld;
    for (const KeptRun& run : runs)
      for (std::size_t t = 0; t < run.count; ++t) {
        const auto x = static_cast<float>(map(row[run.first + t]));
        dst[run.out + t] = cosine ? x * cosine[run.first + t] : x;
      }
  }
}

void transform_runs_cbrt(const BlockMatrix& values, std::span<const KeptRun> runs, const float* cosine,
                         float* out, std::size_t ld) {
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double* row = values.row(i).data();
    float* dst = out + static_cast<std::size_t>(i) * ld;
    for (const KeptRun& run : runs) {
      if (cosine)
        cbrt_run(row + run.first, cosine + run.first, dst + run.out, run.count);
      else
        cbrt_run(row + run.first, dst + run.out, run.count);
    }
  }
}

}  // namespace

void transform_kept(const BlockMatrix& values, std::span<const KeptRun> runs, const LayoutTransform& layout,
                    const float* cosine, float* out, std::size_t ld) {
  const float* weight = layout.cosine_weighted ? cosine : nullptr;
  switch (layout.map) {
    case LayoutTransform::Map::linear:
      transform_runs(values, runs, [](double x) { return x; }, weight, out, ld);
      break;
    case LayoutTransform::Map::cube_root:
      transform_runs_cbrt(values, runs, weight, out, ld);
      break;
    case LayoutTransform::Map::log:
      transform_runs(values, runs, [](double x) { return std::log1p(100.0 * std::max(x, 0.0)); }, weight, out, ld);
      break;
  }
}

}  // namespace matlas
