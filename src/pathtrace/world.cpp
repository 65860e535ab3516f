#include "pathtrace/world.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>

#include "core/error.h"
#include "formats/mesh_io.h"
#include "render/assets.h"
#include "render/embree_device.h"
#include "render/scene.h"

namespace matlas::pathtrace {

// Outside the anonymous namespace: World::Impl holds these (a member whose type has internal
// linkage draws -Wsubobject-linkage when files are compiled together as a unity build).
struct ObjectTriangles {
  std::vector<Vec3> positions, normals;
  std::vector<std::array<std::uint32_t, 3>> indices;
};

namespace {

ObjectTriangles quad_triangles(const ObjectSpec& o) {
  ObjectTriangles t;
  t.positions = {o.corner, o.corner + o.edge1, o.corner + o.edge1 + o.edge2, o.corner + o.edge2};
  const Vec3 n = o.edge1.cross(o.edge2).normalized();
  t.normals.assign(4, n);
  t.indices = {{0, 1, 2}, {0, 2, 3}};
  return t;
}

/// A mesh by name: ASSETS/models/NAME.obj when installed (the teapot of scripts/install-assets.sh),
/// else render's lookup (a file path, or ASSETS/models/NAME.glb).
std::filesystem::path object_mesh_path(const std::string& name) {
  if (const auto dir = assets_dir(); dir && name.find('/') == std::string::npos && name.find('.') == std::string::npos) {
    const std::filesystem::path obj = *dir / "models" / (name + ".obj");
    if (std::filesystem::exists(obj)) return obj;
  }
  return resolve_mesh(name);
}

ObjectTriangles mesh_triangles(const ObjectSpec& o) {
  TriangleMesh mesh = read_mesh(object_mesh_path(o.mesh));
  render::normalize_mesh(mesh);
  if (mesh.normals.size() != mesh.positions.size()) mesh.compute_normals();
  const double a = o.rotate_y * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  const auto turn = [&](const Eigen::Vector3f& v) {
    const Vec3 d = v.cast<double>();
    return Vec3(c * d.x() + s * d.z(), d.y(), -s * d.x() + c * d.z());
  };
  ObjectTriangles t;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    t.positions.push_back(o.center + o.radius * turn(mesh.positions[i]));
    t.normals.push_back(turn(mesh.normals[i]).normalized());
  }
  t.indices = mesh.triangles;
  if (o.rest_on) {
    double lowest = t.positions.front().y();
    for (const Vec3& p : t.positions) lowest = std::min(lowest, p.y());
    for (Vec3& p : t.positions) p.y() += *o.rest_on - lowest;
  }
  return t;
}

/// An Embree ray (fields in declaration order: origin, tnear, direction, time, tfar, mask, id, flags).
RTCRay embree_ray(const Vec3& origin, const Vec3& dir, double tmin, double tmax) {
  const Eigen::Vector3f o = origin.cast<float>(), d = dir.cast<float>();
  return RTCRay{o.x(), o.y(), o.z(), static_cast<float>(tmin), d.x(), d.y(), d.z(), 0.0f,
                static_cast<float>(std::min(tmax, 3.0e38)), 0xffffffffu, 0u, 0u};
}

}  // namespace

struct World::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<ObjectTriangles> triangles;            // per object (empty for spheres)
  // Emitting triangles: object, triangle and the cumulative area up to and including it.
  std::vector<std::pair<int, std::uint32_t>> lights;
  std::vector<double> light_cdf;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
};

World::World(SceneSpec spec) : spec_(std::move(spec)), impl_(std::make_unique<Impl>()) {
  const EnvironmentSpec& e = spec_.environment;
  if (!e.map.empty())
    environment_ = render::Environment::load(resolve_environment(e.map), e.rotation, e.intensity);
  else if ((e.constant * e.intensity).maxCoeff() > 0)
    environment_ = render::Environment::constant(e.constant * e.intensity);

  Impl& s = *impl_;
  s.device = render::embree_device();
  s.scene = rtcNewScene(s.device);
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
  s.triangles.resize(spec_.objects.size());
  double area = 0;
  for (std::size_t i = 0; i < spec_.objects.size(); ++i) {
    const ObjectSpec& o = spec_.objects[i];
    if (o.surface.kind == SurfaceSpec::Kind::measured) measured_ = static_cast<int>(i);
    RTCGeometry g = nullptr;
    if (o.shape == "sphere") {
      g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* v = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
      for (int c = 0; c < 3; ++c) v[c] = static_cast<float>(o.center[c]);
      v[3] = static_cast<float>(o.radius);
    } else {
      ObjectTriangles t = o.shape == "quad" ? quad_triangles(o) : mesh_triangles(o);
      g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), t.positions.size()));
      for (std::size_t k = 0; k < t.positions.size(); ++k)
        for (int c = 0; c < 3; ++c) v[3 * k + static_cast<std::size_t>(c)] = static_cast<float>(t.positions[k][c]);
      auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), t.indices.size()));
      for (std::size_t k = 0; k < t.indices.size(); ++k)
        for (int c = 0; c < 3; ++c) idx[3 * k + static_cast<std::size_t>(c)] = t.indices[k][static_cast<std::size_t>(c)];
      if (o.emission.maxCoeff() > 0) {
        for (std::uint32_t k = 0; k < t.indices.size(); ++k) {
          const auto& tri = t.indices[k];
          area += 0.5 * (t.positions[tri[1]] - t.positions[tri[0]]).cross(t.positions[tri[2]] - t.positions[tri[0]]).norm();
          s.lights.emplace_back(static_cast<int>(i), k);
          s.light_cdf.push_back(area);
        }
      }
      s.triangles[i] = std::move(t);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(s.scene, g, static_cast<unsigned>(i));
    rtcReleaseGeometry(g);
  }
  light_area_ = area;
  rtcCommitScene(s.scene);
  if (rtcGetDeviceError(s.device) != RTC_ERROR_NONE) throw Error("Embree failed to build the scene");
}

World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

std::optional<SurfaceHit> World::intersect(const Vec3& origin, const Vec3& dir, double tmin) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{embree_ray(origin, dir, tmin, std::numeric_limits<float>::infinity()), {}};
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  SurfaceHit hit;
  hit.object = static_cast<int>(rh.hit.geomID);
  const ObjectSpec& o = object(hit.object);
  double t = rh.ray.tfar;
  if (o.shape == "sphere") {
    // Refine in double precision: |origin + t dir - center| = radius.
    const Vec3 oc = origin - o.center;
    const double b = oc.dot(dir), c = oc.squaredNorm() - o.radius * o.radius;
    const double disc = b * b - c;
    if (disc >= 0) {
      const double sq = std::sqrt(disc);
      t = (-b - sq > tmin) ? -b - sq : -b + sq;
    }
    hit.position = origin + t * dir;
    hit.geometric_normal = hit.normal = (hit.position - o.center).normalized();
  } else {
    hit.position = origin + t * dir;
    const ObjectTriangles& tr = impl_->triangles[static_cast<std::size_t>(hit.object)];
    const auto& tri = tr.indices[rh.hit.primID];
    hit.geometric_normal = (tr.positions[tri[1]] - tr.positions[tri[0]]).cross(tr.positions[tri[2]] - tr.positions[tri[0]]).normalized();
    const double u = rh.hit.u, v = rh.hit.v;
    const Vec3 n = (1.0 - u - v) * tr.normals[tri[0]] + u * tr.normals[tri[1]] + v * tr.normals[tri[2]];
    hit.normal = n.norm() > 0 ? Vec3(n.normalized()) : hit.geometric_normal;
  }
  hit.front = hit.geometric_normal.dot(dir) < 0;
  if (!hit.front) hit.geometric_normal = -hit.geometric_normal;
  if (hit.normal.dot(hit.geometric_normal) < 0) hit.normal = -hit.normal;
  return hit;
}

bool World::occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = embree_ray(origin, dir, tmin, tmax);
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

LightSample World::sample_light(double u0, double u1, double u2) const {
  const Impl& s = *impl_;
  const double target = u0 * light_area_;
  std::size_t k = static_cast<std::size_t>(std::upper_bound(s.light_cdf.begin(), s.light_cdf.end(), target) - s.light_cdf.begin());
  if (k >= s.lights.size()) k = s.lights.size() - 1;
  const auto [obj, tri_index] = s.lights[k];
  const ObjectTriangles& tr = s.triangles[static_cast<std::size_t>(obj)];
  const auto& tri = tr.indices[tri_index];
  const double su = std::sqrt(u1);
  const double b0 = 1.0 - su, b1 = u2 * su;
  LightSample l;
  l.position = b0 * tr.positions[tri[0]] + b1 * tr.positions[tri[1]] + (1.0 - b0 - b1) * tr.positions[tri[2]];
  l.normal = (tr.positions[tri[1]] - tr.positions[tri[0]]).cross(tr.positions[tri[2]] - tr.positions[tri[0]]).normalized();
  l.emission = object(obj).emission;
  l.pdf_area = light_pdf_area();
  return l;
}

}  // namespace matlas::pathtrace
