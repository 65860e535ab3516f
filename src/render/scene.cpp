#include "render/scene.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "render/assets.h"
#include "render/geometry.h"

namespace matlas::render {

namespace {

constexpr unsigned kObjectGeometry = 0;  // the ground, when there is one, is shape 1
constexpr double kGroundHalfSize = 50.0;

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
  if (const std::string problem = camera_problem(d.camera); !problem.empty()) fail(problem);
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
  Geometry geometry;  // shape kObjectGeometry, then the ground
};

Scene::Scene(const SceneDescription& description)
    : Scene(description, load_object(validated(description)), load_environment(validated(description))) {}

Scene::Scene(const SceneDescription& description, std::optional<TriangleMesh> mesh, Environment environment)
    : description_(description), environment_(std::move(environment)) {
  validate_description(description_);
  build(std::move(mesh));
}

Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

void Scene::build(std::optional<TriangleMesh> mesh) {
  impl_ = std::make_unique<Impl>();
  Impl& s = *impl_;
  float ground_y = -1.0f;
  if (!mesh) {
    s.geometry.add_sphere(Vec3::Zero(), 1.0);
  } else {
    normalize_mesh(*mesh);
    if (mesh->normals.size() != mesh->positions.size()) mesh->compute_normals();
    Geometry::Triangles t;
    t.positions.reserve(mesh->positions.size());
    t.normals.reserve(mesh->normals.size());
    ground_y = 1.0f;
    for (const Eigen::Vector3f& p : mesh->positions) {
      t.positions.push_back(p.cast<double>());
      ground_y = std::min(ground_y, p.y());
    }
    for (const Eigen::Vector3f& n : mesh->normals) t.normals.push_back(n.cast<double>());
    t.indices = std::move(mesh->triangles);
    s.geometry.add_triangles(std::move(t), Geometry::GeometricNormal::embree);
  }
  if (description_.ground) {
    const double h = kGroundHalfSize, y = ground_y;
    s.geometry.add_quad({Vec3(-h, y, -h), Vec3(-h, y, h), Vec3(h, y, h), Vec3(h, y, -h)}, Vec3(0, 1, 0));
  }
  s.geometry.commit();
}

std::optional<Hit> Scene::intersect(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  const auto g = impl_->geometry.intersect(origin, dir, tmin, std::min(tmax, 1e30));
  if (!g) return std::nullopt;
  Hit hit;
  hit.object = g->shape == kObjectGeometry;
  hit.position = g->position;
  hit.normal = g->normal;
  hit.geometric_normal = g->geometric_normal;
  return hit;
}

bool Scene::occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  return impl_->geometry.occluded(origin, dir, tmin, std::min(tmax, 1e30));
}

}  // namespace matlas::render
