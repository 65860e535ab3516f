#pragma once
// The description of a path-traced scene (docs/GI.md): camera, environment and objects, read
// from a small JSON file or taken from the built-in scenes. Exactly one object may carry the
// "measured" material: the object whose tabulated BRDF the GI image basis varies.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "brdf/types.h"
#include "render/camera.h"
#include "render/directional_light.h"

namespace matlas::pathtrace {

/// The surface of an object. lambert: albedo / pi. ggx: albedo / pi plus a GGX microfacet lobe
/// (Schlick Fresnel from `specular` at normal incidence, roughness `alpha`, height-correlated
/// Smith masking). measured: the tabulated BRDF given at render time.
struct SurfaceSpec {
  enum class Kind { lambert, ggx, measured };
  Kind kind = Kind::lambert;
  Rgb albedo = Rgb::Constant(0.5);
  Rgb specular = Rgb::Constant(0.04);
  double alpha = 0.2;
};

/// One object. shape "sphere" (exact: center, radius), "quad" (corner, edge1, edge2; its front
/// side, the one that emits, faces edge1 x edge2) or "mesh" (a mesh name or file, scaled into a
/// sphere of `radius` at `center`, turned by `rotate_y` degrees, and with `rest_on` set moved
/// vertically so that its lowest vertex lies at y = rest_on). A non-zero `emission` makes the
/// object an area light (one-sided for quads and meshes; spheres cannot emit).
struct ObjectSpec {
  std::string shape = "sphere";
  std::string mesh;
  Vec3 center = Vec3::Zero();
  double radius = 1.0;
  double rotate_y = 0.0;
  std::optional<double> rest_on;
  Vec3 corner = Vec3::Zero(), edge1 = Vec3(1, 0, 0), edge2 = Vec3(0, 0, 1);
  SurfaceSpec surface;
  Rgb emission = Rgb::Zero();
};

/// map: an installed map name or an .exr/.hdr file; else a constant radiance (zero: no
/// environment light).
struct EnvironmentSpec {
  std::string map;
  Rgb constant = Rgb::Zero();
  double rotation = 0.0;   ///< degrees about +y
  double intensity = 1.0;
  /// Whether camera rays that escape see the environment (false: black there; the environment
  /// still lights the scene, and reflections show it).
  bool visible = true;
};

struct SceneSpec {
  std::string name;
  /// The one camera of previews and GI (render/camera.h); a scene file's defaults differ from a
  /// preview's: at (0, 1, 5), 35 degrees.
  render::Camera camera{.orthographic = false, .position = Vec3(0, 1, 5), .target = Vec3::Zero(), .fov_degrees = 35.0};
  EnvironmentSpec environment;
  /// Lights infinitely far away, sampled at every vertex (docs/GI.md).
  std::vector<render::DirectionalLight> lights;
  std::vector<ObjectSpec> objects;
};

/// Parses a scene; `source` names the file in error messages (matlas::Error naming the key for
/// unknown keys, wrong types, bad values (coordinates, radii, angles, intensities and
/// irradiances beyond render::kMaxSceneCoordinate, a camera target within 1e-6 of its position, a
/// light direction shorter than 1e-6), several measured objects).
SceneSpec parse_scene(const nlohmann::json& j, const std::string& source);
/// The scene as JSON (parse_scene(scene_to_json(s)) gives s back): stored in GI bases.
nlohmann::json scene_to_json(const SceneSpec& scene);

/// Names of the built-in scenes: "floor" (the object on a glossy floor in front of a wall, under
/// an environment map) and "box" (a closed box with coloured walls and an area light).
std::vector<std::string> builtin_scenes();
/// The camera views of a built-in scene ("front", its own camera, "side", "above"); none for
/// other names. Scene "NAME@VIEW" is the built-in scene NAME seen from VIEW.
std::vector<std::string> builtin_views(const std::string& scene);
/// A built-in scene by name (or NAME@VIEW) with `object` ("sphere", "bunny", "suzi" or a mesh
/// file) as its measured object, or a JSON scene file (then `object` is ignored). matlas::Error
/// otherwise.
SceneSpec load_scene(const std::string& name_or_path, const std::string& object = "sphere");
/// Whether `name_or_path` is what load_scene reads: a built-in scene, NAME@VIEW of one, or a
/// .json file (an object's name or mesh file is not).
bool is_scene(const std::string& name_or_path);

}  // namespace matlas::pathtrace
