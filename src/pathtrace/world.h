#pragma once
// A scene ready to trace: the objects of a SceneSpec as one render::Geometry (render/geometry.h:
// exact spheres; quads and meshes as triangles, their geometric normals from the double
// positions), the environment, the area lights (every emitting triangle, sampled by area), the
// directional lights and the camera.
#include <memory>
#include <optional>
#include <vector>

#include "pathtrace/scene_spec.h"
#include "render/environment.h"
#include "render/sampling.h"

namespace matlas::pathtrace {

/// A surface point found by a ray.
struct SurfaceHit {
  int object = -1;         ///< index into SceneSpec::objects
  Vec3 position;
  Vec3 normal;             ///< shading normal, on the side the ray came from
  Vec3 geometric_normal;   ///< on the side the ray came from
  bool front = true;       ///< the ray hit the geometric front side (emitters emit from it)
};

/// A point drawn on the area lights.
struct LightSample {
  Vec3 position;
  Vec3 normal;             ///< front side of the emitter
  Rgb emission = Rgb::Zero();
  double pdf_area = 0;     ///< density per unit area over all emitters
};

class World {
public:
  /// Loads meshes and maps (matlas::Error naming the file) and builds the ray-tracing scene.
  explicit World(SceneSpec spec);
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  ~World();

  const SceneSpec& spec() const { return spec_; }
  const ObjectSpec& object(int i) const { return spec_.objects[static_cast<std::size_t>(i)]; }
  /// Index of the measured object, or -1.
  int measured_object() const { return measured_; }

  std::optional<SurfaceHit> intersect(const Vec3& origin, const Vec3& dir, double tmin = 0.0) const;
  bool occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const;

  /// Whether the environment gives light (a map, or a non-zero constant).
  bool has_environment() const { return environment_.has_value(); }
  const render::Environment& environment() const { return *environment_; }

  /// The scene's directional lights that give light, their directions unit vectors.
  const std::vector<render::DirectionalLight>& directional_lights() const { return directional_lights_; }

  bool has_lights() const { return light_area_ > 0; }
  /// A point uniformly distributed by area over every emitting triangle.
  LightSample sample_light(double u0, double u1, double u2) const;
  /// Density per unit area of sample_light (uniform over the emitters' total area).
  double light_pdf_area() const { return 1.0 / light_area_; }

  /// Primary ray through image position (px, py) in pixels of a width x height image: the
  /// scene's camera (render::camera_ray).
  void camera_ray(double px, double py, int width, int height, Vec3* origin, Vec3* dir) const {
    render::camera_ray(spec_.camera, px, py, width, height, origin, dir);
  }

private:
  struct Impl;
  SceneSpec spec_;
  int measured_ = -1;
  std::optional<render::Environment> environment_;
  std::vector<render::DirectionalLight> directional_lights_;
  double light_area_ = 0;
  std::unique_ptr<Impl> impl_;
};

}  // namespace matlas::pathtrace
