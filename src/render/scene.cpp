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

/// Refuses what would reach Embree as infinities or lose all precision in single precision (a
/// camera at 1e308 tripped an assertion in Embree: SIGABRT), naming the field.
void validate_description(const SceneDescription& d) {
  auto fail = [](const std::string& what) { throw Error("scene: " + what); };
  if (const std::string problem = camera_problem(d.camera); !problem.empty()) fail(problem);
  for (std::size_t i = 0; i < d.lights.size(); ++i)
    if (const std::string problem = light_problem(d.lights[i], "lights[" + std::to_string(i) + "]"); !problem.empty())
      fail(problem);
  if (!std::isfinite(d.environment_rotation)) fail("environment_rotation must be finite");
  if (!std::isfinite(d.environment_intensity)) fail("environment_intensity must be finite");
}

/// The description after validate_description (arguments are evaluated in no set order: each
/// loader's argument validates, so that nothing is read for a description that is refused).
const SceneDescription& validated(const SceneDescription& d) {
  validate_description(d);
  return d;
}

/// Scales and centres a mesh into the unit sphere at the origin (bounding-box centre, radius of
/// the farthest vertex = 1).
void normalize_mesh(TriangleMesh& mesh) {
  const auto [lo, hi] = mesh.bounds();
  const Eigen::Vector3f centre = 0.5f * (lo + hi);
  float radius = 0;
  for (const auto& p : mesh.positions) radius = std::max(radius, (p - centre).norm());
  if (!(radius > 0)) throw Error("mesh has no extent");
  for (auto& p : mesh.positions) p = (p - centre) / radius;
}

}  // namespace

PlacedObject place_object(std::optional<TriangleMesh> mesh) {
  float lowest = -1.0f;
  if (mesh) {
    normalize_mesh(*mesh);
    if (mesh->normals.size() != mesh->positions.size()) mesh->compute_normals();
    lowest = 1.0f;
    for (const Eigen::Vector3f& p : mesh->positions) lowest = std::min(lowest, p.y());
  }
  const double h = kGroundHalfSize, y = lowest;
  return {std::move(mesh), {Vec3(-h, y, -h), Vec3(-h, y, h), Vec3(h, y, h), Vec3(h, y, -h)}};
}

std::optional<TriangleMesh> read_object(const SceneDescription& d) {
  if (d.object == "sphere") return std::nullopt;
  return read_mesh(resolve_mesh(d.object));
}

struct Scene::Impl {
  Geometry geometry;  // shape kObjectGeometry, then the ground
};

Scene::Scene(const SceneDescription& description)
    : Scene(description, read_object(validated(description)), load_environment(validated(description))) {}

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
  PlacedObject placed = place_object(std::move(mesh));
  if (!placed.mesh) {
    s.geometry.add_sphere(Vec3::Zero(), 1.0);
  } else {
    TriangleMesh& m = *placed.mesh;
    Geometry::Triangles t;
    t.positions.reserve(m.positions.size());
    t.normals.reserve(m.normals.size());
    for (const Eigen::Vector3f& p : m.positions) t.positions.push_back(p.cast<double>());
    for (const Eigen::Vector3f& n : m.normals) t.normals.push_back(n.cast<double>());
    t.indices = std::move(m.triangles);
    s.geometry.add_triangles(std::move(t), Geometry::GeometricNormal::embree);
  }
  if (description_.ground) s.geometry.add_quad(placed.ground, Vec3(0, 1, 0));
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
