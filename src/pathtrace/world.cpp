#include "pathtrace/world.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/error.h"
#include "formats/mesh_io.h"
#include "render/assets.h"
#include "render/geometry.h"
#include "render/scene.h"

namespace matlas::pathtrace {

namespace {

using ObjectTriangles = render::Geometry::Triangles;

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
  // Into the unit sphere at the origin with vertex normals, as previews place their object.
  TriangleMesh mesh = *render::place_object(read_mesh(object_mesh_path(o.mesh))).mesh;
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

}  // namespace

struct World::Impl {
  render::Geometry geometry;  // shape i is object i
  // Emitting triangles: object, triangle and the cumulative area up to and including it.
  std::vector<std::pair<int, std::uint32_t>> lights;
  std::vector<double> light_cdf;
};

World::World(SceneSpec spec) : spec_(std::move(spec)), impl_(std::make_unique<Impl>()) {
  const EnvironmentSpec& e = spec_.environment;
  if (!e.map.empty())
    environment_ = render::Environment::load(resolve_environment(e.map), e.rotation, e.intensity);
  else if ((e.constant * e.intensity).maxCoeff() > 0)
    environment_ = render::Environment::constant(e.constant * e.intensity);
  for (const render::DirectionalLight& l : spec_.lights)
    if (l.irradiance.maxCoeff() > 0) directional_lights_.push_back({l.direction.normalized(), l.irradiance});

  Impl& s = *impl_;
  double area = 0;
  for (std::size_t i = 0; i < spec_.objects.size(); ++i) {
    const ObjectSpec& o = spec_.objects[i];
    if (o.surface.kind == SurfaceSpec::Kind::measured) measured_ = static_cast<int>(i);
    if (o.shape == "sphere") {
      s.geometry.add_sphere(o.center, o.radius);
      continue;
    }
    ObjectTriangles t = o.shape == "quad" ? quad_triangles(o) : mesh_triangles(o);
    if (o.emission.maxCoeff() > 0) {
      for (std::uint32_t k = 0; k < t.indices.size(); ++k) {
        const auto& tri = t.indices[k];
        area += 0.5 * (t.positions[tri[1]] - t.positions[tri[0]]).cross(t.positions[tri[2]] - t.positions[tri[0]]).norm();
        s.lights.emplace_back(static_cast<int>(i), k);
        s.light_cdf.push_back(area);
      }
    }
    s.geometry.add_triangles(std::move(t), render::Geometry::GeometricNormal::positions);
  }
  light_area_ = area;
  s.geometry.commit();
}

World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

std::optional<SurfaceHit> World::intersect(const Vec3& origin, const Vec3& dir, double tmin) const {
  const auto g = impl_->geometry.intersect(origin, dir, tmin, std::numeric_limits<double>::infinity());
  if (!g) return std::nullopt;
  SurfaceHit hit;
  hit.object = static_cast<int>(g->shape);
  hit.position = g->position;
  hit.normal = g->normal;
  hit.geometric_normal = g->geometric_normal;
  hit.front = g->front;
  return hit;
}

bool World::occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
  return impl_->geometry.occluded(origin, dir, tmin, tmax);
}

LightSample World::sample_light(double u0, double u1, double u2) const {
  const Impl& s = *impl_;
  MATLAS_DCHECK(!s.lights.empty() && s.light_cdf.size() == s.lights.size(), "sampled only when there are lights");
  const double target = u0 * light_area_;
  std::size_t k = static_cast<std::size_t>(std::upper_bound(s.light_cdf.begin(), s.light_cdf.end(), target) - s.light_cdf.begin());
  if (k >= s.lights.size()) k = s.lights.size() - 1;
  const auto [obj, tri_index] = s.lights[k];
  const ObjectTriangles& tr = s.geometry.triangles(static_cast<unsigned>(obj));
  MATLAS_DCHECK_LT(static_cast<std::size_t>(tri_index), tr.indices.size());
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
