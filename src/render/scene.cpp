#include "render/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>

#include "core/error.h"
#include "render/assets.h"
#include "render/embree_device.h"

namespace matlas::render {

namespace {

constexpr unsigned kObjectGeometry = 0;
constexpr unsigned kGroundGeometry = 1;
constexpr float kGroundHalfSize = 50.0f;

Environment load_environment(const SceneDescription& d) {
  if (d.environment == "constant") return Environment::constant(d.constant_radiance * d.environment_intensity);
  return Environment::load(resolve_environment(d.environment), d.environment_rotation, d.environment_intensity);
}

std::optional<TriangleMesh> load_object(const SceneDescription& d) {
  if (d.object == "sphere") return std::nullopt;
  return read_mesh(resolve_mesh(d.object));
}

/// Refuses what would reach Embree as infinities or lose all precision in single precision (a
/// camera at 1e308 tripped an assertion in Embree: SIGABRT), naming the field.
void validate_description(const SceneDescription& d) {
  auto fail = [](const std::string& what) { throw Error("scene: " + what); };
  auto check_point = [&](const Vec3& v, const char* key) {
    if (!v.allFinite() || !(v.cwiseAbs().maxCoeff() <= kMaxSceneCoordinate))  // maxCoeff may skip a NaN
      fail(std::string(key) + " must be finite, with coordinates within +-1e6");
  };
  const Camera& c = d.camera;
  check_point(c.position, "camera.position");
  check_point(c.target, "camera.target");
  if (!((c.target - c.position).norm() >= 1e-6)) fail("camera.target must differ from camera.position (by 1e-6 at least)");
  if (!(c.fov_degrees > 0 && c.fov_degrees < 180)) fail("camera.fov_degrees must be in (0, 180)");
  if (!(c.ortho_height > 0 && c.ortho_height <= kMaxSceneCoordinate)) fail("camera.ortho_height must be in (0, 1e6]");
  for (const DirectionalLight& l : d.lights) {
    if (!l.direction.allFinite() || !(l.direction.norm() > 0)) fail("a light's direction must be finite and non-zero");
    if (!l.irradiance.allFinite()) fail("a light's irradiance must be finite");
  }
  if (!std::isfinite(d.environment_rotation)) fail("environment_rotation must be finite");
  if (!std::isfinite(d.environment_intensity)) fail("environment_intensity must be finite");
}

/// The description after validate_description (arguments are evaluated in no set order: each
/// loader's argument validates, so that nothing is read for a description that is refused).
const SceneDescription& validated(const SceneDescription& d) {
  validate_description(d);
  return d;
}

}  // namespace

void normalize_mesh(TriangleMesh& mesh) {
  const auto [lo, hi] = mesh.bounds();
  const Eigen::Vector3f centre = 0.5f * (lo + hi);
  float radius = 0;
  for (const auto& p : mesh.positions) radius = std::max(radius, (p - centre).norm());
  if (!(radius > 0)) throw Error("mesh has no extent");
  for (auto& p : mesh.positions) p = (p - centre) / radius;
}

struct Scene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  bool sphere = true;
  std::vector<Eigen::Vector3f> normals;            // mesh shading normals
  std::vector<std::array<std::uint32_t, 3>> triangles;
  float ground_y = -1.0f;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
};

Scene::Scene(const SceneDescription& description)
    : Scene(description, load_object(validated(description)), load_environment(validated(description))) {}

Scene::Scene(const SceneDescription& description, std::optional<TriangleMesh> mesh, Environment environment)
    : description_(description), environment_(std::move(environment)), impl_(std::make_unique<Impl>()) {
  validate_description(description_);
  build(std::move(mesh));
}

Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

void Scene::build(std::optional<TriangleMesh> mesh) {
  Impl& s = *impl_;
  s.device = embree_device();
  s.scene = rtcNewScene(s.device);
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);

  if (!mesh) {
    s.sphere = true;
    RTCGeometry g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), 1));
    v[0] = v[1] = v[2] = 0.0f;
    v[3] = 1.0f;
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(s.scene, g, kObjectGeometry);
    rtcReleaseGeometry(g);
    s.ground_y = -1.0f;
  } else {
    s.sphere = false;
    normalize_mesh(*mesh);
    if (mesh->normals.size() != mesh->positions.size()) mesh->compute_normals();
    RTCGeometry g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh->positions.size()));
    float ymin = 1.0f;
    for (std::size_t i = 0; i < mesh->positions.size(); ++i) {
      for (int c = 0; c < 3; ++c) v[3 * i + static_cast<std::size_t>(c)] = mesh->positions[i][c];
      ymin = std::min(ymin, mesh->positions[i].y());
    }
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh->triangles.size()));
    for (std::size_t i = 0; i < mesh->triangles.size(); ++i)
      for (int c = 0; c < 3; ++c) t[3 * i + static_cast<std::size_t>(c)] = mesh->triangles[i][static_cast<std::size_t>(c)];
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(s.scene, g, kObjectGeometry);
    rtcReleaseGeometry(g);
    s.normals = std::move(mesh->normals);
    s.triangles = std::move(mesh->triangles);
    s.ground_y = ymin;
  }
  if (description_.ground) {
    RTCGeometry g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_QUAD);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), 4));
    const float h = kGroundHalfSize, y = s.ground_y;
    const float corners[4][3] = {{-h, y, -h}, {-h, y, h}, {h, y, h}, {h, y, -h}};
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c) v[3 * i + c] = corners[i][c];
    auto* q = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4,
                                                             4 * sizeof(unsigned), 1));
    q[0] = 0, q[1] = 1, q[2] = 2, q[3] = 3;
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(s.scene, g, kGroundGeometry);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(s.scene);
  if (rtcGetDeviceError(s.device) != RTC_ERROR_NONE) throw Error("Embree failed to build the scene");
}

std::optional<Hit> Scene::intersect(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(origin.x());
  rh.ray.org_y = static_cast<float>(origin.y());
  rh.ray.org_z = static_cast<float>(origin.z());
  rh.ray.dir_x = static_cast<float>(dir.x());
  rh.ray.dir_y = static_cast<float>(dir.y());
  rh.ray.dir_z = static_cast<float>(dir.z());
  rh.ray.tnear = static_cast<float>(tmin);
  rh.ray.tfar = static_cast<float>(std::min(tmax, 1e30));
  rh.ray.mask = 0xffffffffu;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  Hit hit;
  hit.object = rh.hit.geomID == kObjectGeometry;
  double t = rh.ray.tfar;
  if (hit.object && impl_->sphere) {
    // Refine the sphere hit in double precision: |o + t d| = 1.
    const double b = origin.dot(dir), c = origin.squaredNorm() - 1.0;
    const double disc = b * b - c;
    if (disc >= 0) {
      const double s = std::sqrt(disc);
      const double t0 = -b - s, t1 = -b + s;
      t = (t0 > tmin) ? t0 : t1;
    }
  }
  hit.position = origin + t * dir;
  if (!hit.object) {
    hit.geometric_normal = hit.normal = Vec3(0, 1, 0);
  } else if (impl_->sphere) {
    hit.geometric_normal = hit.normal = hit.position.normalized();
  } else {
    hit.geometric_normal = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
    const auto& tri = impl_->triangles[rh.hit.primID];
    const double u = rh.hit.u, v = rh.hit.v;
    const Eigen::Vector3d n = (1.0 - u - v) * impl_->normals[tri[0]].cast<double>() +
                              u * impl_->normals[tri[1]].cast<double>() + v * impl_->normals[tri[2]].cast<double>();
    hit.normal = n.norm() > 0 ? Vec3(n.normalized()) : hit.geometric_normal;
  }
  // Face the side the ray came from (double-sided surfaces).
  if (hit.geometric_normal.dot(dir) > 0) hit.geometric_normal = -hit.geometric_normal;
  if (hit.normal.dot(hit.geometric_normal) < 0) hit.normal = -hit.normal;
  return hit;
}

bool Scene::occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x());
  ray.org_y = static_cast<float>(origin.y());
  ray.org_z = static_cast<float>(origin.z());
  ray.dir_x = static_cast<float>(dir.x());
  ray.dir_y = static_cast<float>(dir.y());
  ray.dir_z = static_cast<float>(dir.z());
  ray.tnear = static_cast<float>(tmin);
  ray.tfar = static_cast<float>(std::min(tmax, 1e30));
  ray.mask = 0xffffffffu;
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

}  // namespace matlas::render
