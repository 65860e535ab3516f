#pragma once
// The unit sphere at the origin as the analytic tests' orthographic camera sees it (on +z,
// looking down -z, a view 2.2 high): the normal the pixel sees, for tests of both integrators.
#include <cmath>
#include <optional>

#include <Eigen/Core>

namespace matlas::test {

/// The sphere's normal at pixel (x, y) of a width x height image, or none outside the sphere or
/// near its silhouette (squared distance from the centre above 0.8).
inline std::optional<Eigen::Vector3d> ortho_sphere_normal(int x, int y, int width, int height) {
  const double sx = (2.0 * (x + 0.5) / width - 1.0) * 1.1;
  const double sy = (1.0 - 2.0 * (y + 0.5) / height) * 1.1;
  const double r2 = sx * sx + sy * sy;
  if (r2 > 0.8) return std::nullopt;
  return Eigen::Vector3d(sx, sy, std::sqrt(1.0 - r2));
}

}  // namespace matlas::test
