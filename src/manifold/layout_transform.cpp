#include "manifold/layout_transform.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/error.h"

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

/// Cube root to ~1e-12 relative error, several times faster than std::cbrt: an exponent-based
/// first guess (within a few percent) refined by two Halley steps (cubic convergence, one
/// division each), branch-free so that the loop vectorises. Only used to place latent points.
inline double fast_cbrt(double x) {
  const double a = std::abs(x);
  double y = std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) / 3 + 0x2A9F7893782DA1CEull);
  for (int k = 0; k < 2; ++k) {
    const double y3 = y * y * y;
    y *= (y3 + 2.0 * a) / (2.0 * y3 + a);
  }
  return std::copysign(a > 0.0 ? y : 0.0, x);
}

template <class Map>
void transform_runs(const BlockMatrix& values, std::span<const KeptRun> runs, Map map, const double* cosine,
                    double* out, std::size_t ld) {
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double* row = values.row(i).data();
    double* dst = out + static_cast<std::size_t>(i) * ld;
    for (const KeptRun& run : runs)
      for (std::size_t t = 0; t < run.count; ++t) {
        const double x = map(row[run.first + t]);
        dst[run.out + t] = cosine ? x * cosine[run.first + t] : x;
      }
  }
}

}  // namespace

void transform_kept(const BlockMatrix& values, std::span<const KeptRun> runs, const LayoutTransform& layout,
                    const double* cosine, double* out, std::size_t ld) {
  const double* weight = layout.cosine_weighted ? cosine : nullptr;
  switch (layout.map) {
    case LayoutTransform::Map::linear:
      transform_runs(values, runs, [](double x) { return x; }, weight, out, ld);
      break;
    case LayoutTransform::Map::cube_root:
      transform_runs(values, runs, fast_cbrt, weight, out, ld);
      break;
    case LayoutTransform::Map::log:
      transform_runs(values, runs, [](double x) { return std::log1p(100.0 * std::max(x, 0.0)); }, weight, out, ld);
      break;
  }
}

}  // namespace matlas
