#pragma once
// The ray-traced geometry of a scene, the one Embree 3 wrapper of previews (render::Scene) and GI
// scenes (pathtrace::World): shapes in one Embree scene on the process's device
// (render/embree_device.h), numbered in the order they are added, and the two ray queries.
//
// Shapes:
//   sphere    exact: Embree finds the hit in single precision, then t is refined in double
//             (|o + t d - c| = r, the nearer root beyond tmin); normal (p - c) / |p - c|.
//   triangles a mesh with per-vertex shading normals, interpolated in double with the hit's
//             barycentrics (the geometric normal where they cancel). Its geometric normal is either
//             Embree's (computed in single precision: previews) or the cross product of the
//             stored double positions (GI: the same normal the area lights are sampled with).
//   quad      a planar quad (Embree's quad primitive) of one given normal (the previews' ground).
// Vertices reach Embree in single precision. A hit's normals face the side the ray came from;
// `front` says whether the ray met the side the shape's normal points to.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "brdf/types.h"

namespace matlas::render {

class Geometry {
public:
  /// A triangle mesh: positions, per-vertex shading normals (same count) and indices.
  struct Triangles {
    std::vector<Vec3> positions, normals;
    std::vector<std::array<std::uint32_t, 3>> indices;
  };
  /// Where a triangle mesh's geometric normal comes from (header comment).
  enum class GeometricNormal { embree, positions };

  /// What a ray found.
  struct Hit {
    unsigned shape = 0;       ///< the index of the shape, in the order of the add_ calls
    double t = 0;             ///< distance along the ray (for a unit direction)
    Vec3 position;
    Vec3 normal;              ///< shading normal, on the side the ray came from
    Vec3 geometric_normal;    ///< on the side the ray came from
    bool front = true;        ///< the ray met the side the shape's normal points to
  };

  /// An empty geometry on the shared Embree device; throws matlas::Error if there is none.
  Geometry();
  Geometry(Geometry&&) noexcept;
  Geometry& operator=(Geometry&&) noexcept;
  ~Geometry();

  /// Each returns the shape's index. Before commit() only.
  unsigned add_sphere(const Vec3& center, double radius);
  unsigned add_triangles(Triangles mesh, GeometricNormal geometric);
  unsigned add_quad(const std::array<Vec3, 4>& corners, const Vec3& normal);
  /// Builds the acceleration structure (high quality); throws matlas::Error if Embree fails.
  void commit();

  /// The mesh of a shape added by add_triangles.
  const Triangles& triangles(unsigned shape) const;

  /// Closest hit along origin + t dir, t in (tmin, tmax) (tmax at most 3e38); nullopt when
  /// nothing is hit. After commit().
  std::optional<Hit> intersect(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const;
  /// Whether anything blocks origin + t dir for t in (tmin, tmax).
  bool occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace matlas::render
