#include "render/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <embree3/rtcore.h>

#include "core/check.h"
#include "core/error.h"
#include "render/embree_device.h"

namespace matlas::render {

namespace {

/// An Embree ray (fields in declaration order: origin, tnear, direction, time, tfar, mask, id,
/// flags); tfar at most 3e38, below float's largest value.
RTCRay embree_ray(const Vec3& origin, const Vec3& dir, double tmin, double tmax) {
  const Eigen::Vector3f o = origin.cast<float>(), d = dir.cast<float>();
  return RTCRay{o.x(), o.y(), o.z(), static_cast<float>(tmin), d.x(), d.y(), d.z(), 0.0f,
                static_cast<float>(std::min(tmax, 3.0e38)), 0xffffffffu, 0u, 0u};
}

}  // namespace

// Outside the anonymous namespace: Geometry::Impl holds these (a member whose type has internal
// linkage draws -Wsubobject-linkage when files are compiled together as a unity build).
enum class GeometryKind { sphere, triangles, quad };

struct GeometryShape {
  GeometryKind kind = GeometryKind::sphere;
  Vec3 center = Vec3::Zero();        // sphere
  double radius = 0;                 // sphere
  Vec3 normal = Vec3::Zero();        // quad
  Geometry::GeometricNormal geometric = Geometry::GeometricNormal::embree;  // triangles
  Geometry::Triangles mesh;          // triangles
};

struct Geometry::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<GeometryShape> shapes;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }

  unsigned attach(RTCGeometry g, GeometryShape shape) {
    const auto id = static_cast<unsigned>(shapes.size());
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, id);
    rtcReleaseGeometry(g);
    shapes.push_back(std::move(shape));
    return id;
  }
};

Geometry::Geometry() : impl_(std::make_unique<Impl>()) {
  impl_->device = embree_device();
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
}

Geometry::Geometry(Geometry&&) noexcept = default;
Geometry& Geometry::operator=(Geometry&&) noexcept = default;
Geometry::~Geometry() = default;

unsigned Geometry::add_sphere(const Vec3& center, double radius) {
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
  for (int c = 0; c < 3; ++c) v[c] = static_cast<float>(center[c]);
  v[3] = static_cast<float>(radius);
  GeometryShape s;
  s.kind = GeometryKind::sphere;
  s.center = center;
  s.radius = radius;
  return impl_->attach(g, std::move(s));
}

unsigned Geometry::add_triangles(Triangles mesh, GeometricNormal geometric) {
  MATLAS_CHECK_EQ(mesh.normals.size(), mesh.positions.size());
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.positions.size()));
  for (std::size_t k = 0; k < mesh.positions.size(); ++k)
    for (int c = 0; c < 3; ++c) v[3 * k + static_cast<std::size_t>(c)] = static_cast<float>(mesh.positions[k][c]);
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh.indices.size()));
  for (std::size_t k = 0; k < mesh.indices.size(); ++k)
    for (int c = 0; c < 3; ++c) idx[3 * k + static_cast<std::size_t>(c)] = mesh.indices[k][static_cast<std::size_t>(c)];
  GeometryShape s;
  s.kind = GeometryKind::triangles;
  s.geometric = geometric;
  s.mesh = std::move(mesh);
  return impl_->attach(g, std::move(s));
}

unsigned Geometry::add_quad(const std::array<Vec3, 4>& corners, const Vec3& normal) {
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_QUAD);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
  for (std::size_t i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) v[3 * i + static_cast<std::size_t>(c)] = static_cast<float>(corners[i][c]);
  auto* q = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), 1));
  q[0] = 0, q[1] = 1, q[2] = 2, q[3] = 3;
  GeometryShape s;
  s.kind = GeometryKind::quad;
  s.normal = normal;
  return impl_->attach(g, std::move(s));
}

void Geometry::commit() {
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) throw Error("Embree failed to build the scene");
}

const Geometry::Triangles& Geometry::triangles(unsigned shape) const {
  MATLAS_CHECK(shape < impl_->shapes.size() && impl_->shapes[shape].kind == GeometryKind::triangles,
               "shape " + std::to_string(shape) + " is not a triangle mesh");
  return impl_->shapes[shape].mesh;
}

std::optional<Geometry::Hit> Geometry::intersect(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{embree_ray(origin, dir, tmin, tmax), {}};
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  Hit hit;
  hit.shape = rh.hit.geomID;
  const GeometryShape& s = impl_->shapes[hit.shape];
  double t = rh.ray.tfar;
  switch (s.kind) {
    case GeometryKind::sphere: {
      // Refine in double precision: |origin + t dir - center| = radius.
      const Vec3 oc = origin - s.center;
      const double b = oc.dot(dir), c = oc.squaredNorm() - s.radius * s.radius;
      const double disc = b * b - c;
      if (disc >= 0) {
        const double sq = std::sqrt(disc);
        t = (-b - sq > tmin) ? -b - sq : -b + sq;
      }
      hit.position = origin + t * dir;
      hit.geometric_normal = hit.normal = (hit.position - s.center).normalized();
      break;
    }
    case GeometryKind::triangles: {
      hit.position = origin + t * dir;
      const Triangles& m = s.mesh;
      const auto& tri = m.indices[rh.hit.primID];
      if (s.geometric == GeometricNormal::embree)
        hit.geometric_normal = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
      else
        hit.geometric_normal = (m.positions[tri[1]] - m.positions[tri[0]]).cross(m.positions[tri[2]] - m.positions[tri[0]]).normalized();
      const double u = rh.hit.u, v = rh.hit.v;
      const Vec3 n = (1.0 - u - v) * m.normals[tri[0]] + u * m.normals[tri[1]] + v * m.normals[tri[2]];
      hit.normal = n.norm() > 0 ? Vec3(n.normalized()) : hit.geometric_normal;
      break;
    }
    case GeometryKind::quad:
      hit.position = origin + t * dir;
      hit.geometric_normal = hit.normal = s.normal;
      break;
  }
  hit.t = t;
  hit.front = hit.geometric_normal.dot(dir) < 0;
  if (!hit.front) hit.geometric_normal = -hit.geometric_normal;
  if (hit.normal.dot(hit.geometric_normal) < 0) hit.normal = -hit.normal;
  return hit;
}

bool Geometry::occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = embree_ray(origin, dir, tmin, tmax);
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

}  // namespace matlas::render
