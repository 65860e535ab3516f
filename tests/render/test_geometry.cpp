// The one Embree wrapper of previews and GI: exact spheres, triangle meshes (both sources of the
// geometric normal), quads, the side a ray meets, and occlusion within (tmin, tmax).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/geometry.h"

namespace matlas::render {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// One triangle in the plane z = 0, its front (counter-clockwise seen from +z) towards +z, with
/// shading normals tilted towards +x at the second vertex.
Geometry::Triangles triangle() {
  Geometry::Triangles t;
  t.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)};
  t.normals = {Vec3(0, 0, 1), Vec3(0.6, 0, 0.8), Vec3(0, 0, 1)};
  t.indices = {{0, 1, 2}};
  return t;
}

TEST(Geometry, SpheresAreExactFromOutsideAndInside) {
  Geometry g;
  EXPECT_EQ(g.add_sphere(Vec3(1, 2, 3), 0.5), 0u);
  g.commit();
  const Vec3 origin(1.1, 2.2, 10.0), dir = Vec3(0, 0, -1);
  const auto hit = g.intersect(origin, dir, 0.0, kInf);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->shape, 0u);
  const double z = 3.0 + std::sqrt(0.25 - 0.01 - 0.04);  // |(0.1, 0.2, z - 3)| = 0.5
  EXPECT_NEAR(hit->position.z(), z, 1e-12);
  EXPECT_NEAR(hit->t, 10.0 - z, 1e-12);
  EXPECT_TRUE(hit->front);
  EXPECT_NEAR((hit->normal - (hit->position - Vec3(1, 2, 3)) / 0.5).norm(), 0.0, 1e-12);
  // From the centre: the far side, met from inside; the normals face the ray's origin.
  const auto inside = g.intersect(Vec3(1, 2, 3), Vec3(1, 0, 0), 0.0, kInf);
  ASSERT_TRUE(inside.has_value());
  EXPECT_NEAR(inside->position.x(), 1.5, 1e-12);
  EXPECT_FALSE(inside->front);
  EXPECT_NEAR((inside->geometric_normal - Vec3(-1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((inside->normal - Vec3(-1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(g.intersect(origin, -dir, 0.0, kInf).has_value());
}

TEST(Geometry, TrianglesInterpolateShadingNormalsAndTakeTheirGeometricNormalFromEitherSource) {
  for (const auto source : {Geometry::GeometricNormal::embree, Geometry::GeometricNormal::positions}) {
    Geometry g;
    EXPECT_EQ(g.add_triangles(triangle(), source), 0u);
    g.commit();
    EXPECT_EQ(g.triangles(0).positions.size(), 3u);
    // At the second vertex's side of the triangle, from the front.
    const auto front = g.intersect(Vec3(0.5, -0.5, 2), Vec3(0, 0, -1), 0.0, kInf);
    ASSERT_TRUE(front.has_value());
    EXPECT_TRUE(front->front);
    EXPECT_NEAR(front->t, 2.0, 1e-6);
    EXPECT_NEAR((front->geometric_normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-7);
    // Barycentrics (0.125, 0.625, 0.25): n = normalise(0.125 (0,0,1) + 0.625 (0.6,0,0.8) + 0.25 (0,0,1)).
    const Vec3 n = Vec3(0.375, 0, 0.875).normalized();
    EXPECT_NEAR((front->normal - n).norm(), 0.0, 1e-6);
    // From behind: the back side; both normals turned towards the ray's origin.
    const auto back = g.intersect(Vec3(0.5, -0.5, -2), Vec3(0, 0, 1), 0.0, kInf);
    ASSERT_TRUE(back.has_value());
    EXPECT_FALSE(back->front);
    EXPECT_NEAR((back->geometric_normal - Vec3(0, 0, -1)).norm(), 0.0, 1e-7);
    EXPECT_NEAR((back->normal + n).norm(), 0.0, 1e-6);
  }
  // The positions' normal is the double-precision cross product of the edges (here met from
  // behind, so turned).
  Geometry g;
  Geometry::Triangles t = triangle();
  for (Vec3& p : t.positions) p = Vec3(p.x(), p.y() * 0.6, p.y() * 0.8);  // the plane 4y = 3z turned
  g.add_triangles(t, Geometry::GeometricNormal::positions);
  g.commit();
  const auto hit = g.intersect(Vec3(0.1, 3, -4), Vec3(0, -0.6, 0.8), 0.0, kInf);
  ASSERT_TRUE(hit.has_value());
  EXPECT_FALSE(hit->front);
  const auto& p = t.positions;
  EXPECT_EQ(hit->geometric_normal, Vec3(-(p[1] - p[0]).cross(p[2] - p[0]).normalized()));
}

TEST(Geometry, QuadsShapesAreNumberedAndOcclusionStaysWithinTheInterval) {
  Geometry g;
  EXPECT_EQ(g.add_sphere(Vec3(0, 1, 0), 1.0), 0u);
  EXPECT_EQ(g.add_quad({Vec3(-5, 0, -5), Vec3(-5, 0, 5), Vec3(5, 0, 5), Vec3(5, 0, -5)}, Vec3(0, 1, 0)), 1u);
  g.commit();
  const auto ground = g.intersect(Vec3(3, 4, 0), Vec3(0, -1, 0), 0.0, kInf);
  ASSERT_TRUE(ground.has_value());
  EXPECT_EQ(ground->shape, 1u);
  EXPECT_NEAR(ground->t, 4.0, 1e-6);
  EXPECT_EQ(ground->normal, Vec3(0, 1, 0));
  EXPECT_TRUE(ground->front);
  const auto sphere = g.intersect(Vec3(0, 4, 0), Vec3(0, -1, 0), 0.0, kInf);
  ASSERT_TRUE(sphere.has_value());
  EXPECT_EQ(sphere->shape, 0u);
  EXPECT_NEAR(sphere->t, 2.0, 1e-12);
  EXPECT_TRUE(g.occluded(Vec3(0, 4, 0), Vec3(0, -1, 0), 0.0, 2.5));
  EXPECT_FALSE(g.occluded(Vec3(0, 4, 0), Vec3(0, -1, 0), 0.0, 1.5));
  EXPECT_FALSE(g.occluded(Vec3(3, 4, 0), Vec3(0, -1, 0), 4.5, kInf));
  EXPECT_TRUE(g.occluded(Vec3(3, 4, 0), Vec3(0, -1, 0), 0.0, kInf));
  EXPECT_FALSE(g.intersect(Vec3(3, 4, 0), Vec3(0, -1, 0), 0.0, 3.0).has_value());
}

}  // namespace
}  // namespace matlas::render
