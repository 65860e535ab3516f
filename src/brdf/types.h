#pragma once
// Small value types shared by every concern: directions and RGB triples.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace matlas {

/// A 3D vector or direction. Directions in a local shading frame have the normal along +z.
using Vec3 = Eigen::Vector3d;
/// Linear RGB, component-wise arithmetic.
using Rgb = Eigen::Array3d;

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace matlas
