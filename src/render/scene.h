#pragma once
// The scene of a material preview: one object (an exact sphere or a triangle mesh, scaled into
// the unit sphere at the origin), an optional diffuse ground plane under it, an environment map,
// directional lights and a camera. Ray queries go through render::Geometry (render/geometry.h):
// the exact sphere, or the mesh with Embree's geometric normals, then the ground as a quad.
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brdf/types.h"
#include "formats/mesh_io.h"
#include "render/camera.h"
#include "render/directional_light.h"
#include "render/environment.h"

namespace matlas::render {

/// What the scene is made of (the part of a render request that is not the material).
struct SceneDescription {
  /// "sphere", an installed mesh name ("bunny", "suzi"), or a .glb/.gltf/.obj path.
  std::string object = "sphere";
  /// An installed map name ("studio"), an .exr/.hdr path, or "constant" (uniform radiance
  /// `constant_radiance`).
  std::string environment = "constant";
  Rgb constant_radiance = Rgb::Constant(1.0);
  double environment_rotation = 0.0;  ///< degrees about +y
  double environment_intensity = 1.0;
  bool ground = false;
  Rgb ground_albedo = Rgb::Constant(0.5);
  std::vector<DirectionalLight> lights;
  Camera camera;
  /// Whether the background shows the environment (else black).
  bool show_environment = true;
};

/// A surface point found by a ray.
struct Hit {
  bool object = false;      ///< the previewed object (else the ground)
  Vec3 position;            ///< world position
  Vec3 normal;              ///< shading normal, facing the ray's origin side
  Vec3 geometric_normal;    ///< facing the ray's origin side
};

class Scene {
public:
  /// Builds the scene; throws matlas::Error naming the file for unreadable meshes or maps, and
  /// naming the field for a camera or light that is not finite, beyond kMaxSceneCoordinate or
  /// degenerate (target at the position), before anything is loaded.
  explicit Scene(const SceneDescription& description);
  /// A scene with an already loaded mesh and environment (tests, servers caching assets).
  Scene(const SceneDescription& description, std::optional<TriangleMesh> mesh, Environment environment);
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  ~Scene();

  const SceneDescription& description() const { return description_; }
  const Environment& environment() const { return environment_; }

  /// Closest hit along origin + t dir, t in (tmin, tmax); nullopt when nothing is hit.
  std::optional<Hit> intersect(const Vec3& origin, const Vec3& dir, double tmin = 0.0,
                               double tmax = 1e30) const;
  /// Whether anything blocks origin + t dir for t in (tmin, tmax).
  bool occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax = 1e30) const;

  /// Primary ray through image position (px, py) in pixels of a width x height image: the
  /// description's camera (render::camera_ray).
  void camera_ray(double px, double py, int width, int height, Vec3* origin, Vec3* dir) const {
    render::camera_ray(description_.camera, px, py, width, height, origin, dir);
  }

private:
  struct Impl;
  void build(std::optional<TriangleMesh> mesh);
  SceneDescription description_;
  Environment environment_;
  std::unique_ptr<Impl> impl_;
};

/// A preview's object as its scene places it, and the ground under it: the one placement of
/// previews, used by Scene and by the GI scene of a preview (pathtrace/preview_scene.h); GI
/// scenes' meshes and the real-time viewer's take their mesh from it too.
struct PlacedObject {
  /// The mesh scaled and centred into the unit sphere at the origin (bounding-box centre, radius
  /// of the farthest vertex = 1), with vertex normals (the file's, else computed); nullopt: the
  /// exact unit sphere at the origin.
  std::optional<TriangleMesh> mesh;
  /// The ground (SceneDescription::ground), facing +y: a square of 100 x 100 centred under the
  /// origin at the object's lowest point (its lowest vertex; y = -1 under the sphere), corners in
  /// order around it.
  std::array<Vec3, 4> ground;
};

/// Places an object as read from its file (nullopt: the sphere). matlas::Error for a mesh
/// without extent.
PlacedObject place_object(std::optional<TriangleMesh> mesh);

/// The mesh of a description's object as read from its file (resolve_mesh; matlas::Error naming
/// the file), nullopt for "sphere".
std::optional<TriangleMesh> read_object(const SceneDescription& description);

}  // namespace matlas::render
