#include "pathtrace/preview_scene.h"

#include <nlohmann/json.hpp>

#include "render/assets.h"

namespace matlas::pathtrace {

SceneSpec preview_scene(const render::SceneDescription& d) {
  SceneSpec s;
  s.name = "preview";
  s.camera = d.camera;
  if (d.environment == "constant") {
    s.environment.constant = d.constant_radiance;
  } else {
    s.environment.map = d.environment;
    s.environment.rotation = d.environment_rotation;
  }
  s.environment.intensity = d.environment_intensity;
  s.environment.visible = d.show_environment;
  s.lights = d.lights;

  ObjectSpec object;
  object.surface.kind = SurfaceSpec::Kind::measured;
  if (d.object != "sphere") {
    // The file the preview reads (a name given to a GI scene may find an .obj first).
    object.shape = "mesh";
    object.mesh = resolve_mesh(d.object).string();
  }
  s.objects.push_back(object);
  if (d.ground) {
    const std::array<Vec3, 4> g = render::place_object(render::read_object(d)).ground;
    ObjectSpec ground;
    ground.shape = "quad";
    ground.corner = g[0];
    ground.edge1 = g[1] - g[0];
    ground.edge2 = g[3] - g[0];
    ground.surface.albedo = d.ground_albedo;
    s.objects.push_back(ground);
  }
  return parse_scene(scene_to_json(s), "scene");
}

}  // namespace matlas::pathtrace
