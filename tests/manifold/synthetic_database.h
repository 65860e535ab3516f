#pragma once
// Small synthetic databases for manifold tests: tables on a reduced grid, each a smooth function
// of a hidden 2D parameter (so a low-dimensional manifold exists), written as MERL files.
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "formats/merl_file.h"
#include "manifold/model.h"

namespace matlas::test {

inline constexpr MerlDims kSmallDims{6, 6, 12};

/// Table of a hidden parameter (a, b): a lobe whose sharpness and colour vary with (a, b).
inline BrdfTable smooth_table(double a, double b, const MerlDims& dims = kSmallDims) {
  BrdfTable t(dims);
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const double th = (i + 0.5) / dims.theta_h, td = (j + 0.5) / dims.theta_d;
        const double lobe = std::exp(-th * th * (2.0 + 20.0 * a)) * (1.0 + 0.3 * td * b);
        for (int c = 0; c < 3; ++c)
          t.set_value(c, dims.flat(i, j, k), 0.05 + (0.5 + 0.4 * std::sin(a * 3 + c + b)) * lobe);
      }
  return t;
}

/// Writes `count` tables with parameters drawn from `seed`; returns the paths (sorted by name).
inline std::vector<std::filesystem::path> write_database(const std::filesystem::path& dir, int count,
                                                         unsigned seed = 1, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::filesystem::path> paths;
  std::filesystem::create_directories(dir);
  for (int m = 0; m < count; ++m) {
    // Two statements: the order of a call's arguments is unspecified (GCC draws the last one
    // first, Clang the first), and the database must not depend on the compiler.
    const double b = u(rng);
    const double a = u(rng);
    BrdfTable t = smooth_table(a, b);
    for (double& v : t.stored()) v *= scale;
    char name[32];
    std::snprintf(name, sizeof name, "mat%02d.binary", m);
    paths.push_back(dir / name);
    write_merl(paths.back(), t, /*allow_nonstandard_dims=*/true);
  }
  return paths;
}

/// Relative L2 distance of table a from table b over the values the model keeps.
inline double relative_l2(const BrdfTable& a, const BrdfTable& b, const Model& m) {
  double e = 0, n = 0;
  for (std::size_t v = 0; v < a.size(); ++v) {
    if (!m.kept(v)) continue;
    const int c = static_cast<int>(v / a.bins());
    const double x = a.value(c, v % a.bins()), y = b.value(c, v % a.bins());
    e += (x - y) * (x - y);
    n += y * y;
  }
  return std::sqrt(e / n);
}

}  // namespace matlas::test
