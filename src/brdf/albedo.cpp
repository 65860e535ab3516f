#include "brdf/albedo.h"

#include "core/parallel.h"

namespace matlas {

std::vector<Vec3> cosine_quadrature(int resolution) {
  std::vector<Vec3> dirs;
  dirs.reserve(static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution));
  for (int a = 0; a < resolution; ++a) {
    const double u = (a + 0.5) / resolution;
    const double r = std::sqrt(u);
    const double z = std::sqrt(std::max(0.0, 1.0 - u));
    for (int b = 0; b < resolution; ++b) {
      const double phi = 2.0 * kPi * (b + 0.5) / resolution;
      dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
  }
  return dirs;
}

Rgb directional_albedo(const BrdfTable& table, double theta_o, int resolution) {
  const Vec3 wo = direction_at_theta(theta_o);
  return directional_albedo([&](const Vec3& wi, const Vec3& o) { return table.lookup(wi, o); }, wo,
                            resolution);
}

std::vector<Rgb> albedo_curve(const BrdfTable& table, int count, int resolution) {
  std::vector<Rgb> curve(static_cast<std::size_t>(count));
  parallel_for(0, curve.size(), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i)
      curve[i] = directional_albedo(table, (i + 0.5) / count * (kPi / 2.0), resolution);
  });
  return curve;
}

}  // namespace matlas
