#include "pathtrace/scene_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_io.h"
#include "render/scene.h"

namespace matlas::pathtrace {

namespace {

using nlohmann::json;
using render::kMaxSceneCoordinate;

// The built-in scenes, in the file format itself ("$object" is replaced by the object's name).
constexpr const char* kFloorScene = R"({
  "name": "floor",
  "camera": {"position": [0, 1.7, 5.6], "target": [0, 0.85, 0], "fov": 34},
  "environment": {"map": "studio", "intensity": 0.3, "rotation": 180},
  "objects": [
    {"shape": "mesh", "mesh": "$object", "center": [0, 1, 0], "radius": 1,
     "material": {"type": "measured"}},
    {"shape": "quad", "corner": [-8, 0, -8], "edge1": [0, 0, 16], "edge2": [16, 0, 0],
     "material": {"type": "ggx", "albedo": [0.12, 0.12, 0.13], "specular": [0.25, 0.25, 0.25], "alpha": 0.04}},
    {"shape": "quad", "corner": [-8, 0, -2.2], "edge1": [16, 0, 0], "edge2": [0, 8, 0],
     "material": {"type": "lambert", "albedo": [0.62, 0.58, 0.52]}}
  ]
})";

constexpr const char* kBoxScene = R"({
  "name": "box",
  "camera": {"position": [0, 2, 3.9], "target": [0, 1.8, 0], "fov": 55},
  "objects": [
    {"shape": "mesh", "mesh": "$object", "center": [0, 1, -0.3], "radius": 1,
     "material": {"type": "measured"}},
    {"shape": "quad", "corner": [-2, 0, -2], "edge1": [0, 0, 6], "edge2": [4, 0, 0],
     "material": {"type": "lambert", "albedo": [0.73, 0.73, 0.73]}},
    {"shape": "quad", "corner": [-2, 4, -2], "edge1": [4, 0, 0], "edge2": [0, 0, 6],
     "material": {"type": "lambert", "albedo": [0.73, 0.73, 0.73]}},
    {"shape": "quad", "corner": [-2, 0, -2], "edge1": [4, 0, 0], "edge2": [0, 4, 0],
     "material": {"type": "lambert", "albedo": [0.73, 0.73, 0.73]}},
    {"shape": "quad", "corner": [-2, 0, 4], "edge1": [0, 4, 0], "edge2": [4, 0, 0],
     "material": {"type": "lambert", "albedo": [0.73, 0.73, 0.73]}},
    {"shape": "quad", "corner": [-2, 0, -2], "edge1": [0, 4, 0], "edge2": [0, 0, 6],
     "material": {"type": "lambert", "albedo": [0.63, 0.065, 0.05]}},
    {"shape": "quad", "corner": [2, 0, -2], "edge1": [0, 0, 6], "edge2": [0, 4, 0],
     "material": {"type": "lambert", "albedo": [0.14, 0.45, 0.09]}},
    {"shape": "quad", "corner": [-0.8, 3.99, -1.1], "edge1": [1.6, 0, 0], "edge2": [0, 0, 1.6],
     "emission": [8, 6.8, 5.1]}
  ]
})";

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw Error(source + ": " + what);
}

void check_keys(const json& j, const std::set<std::string>& allowed, const std::string& source,
                const std::string& where) {
  if (!j.is_object()) fail(source, where + " must be an object");
  for (const auto& [key, value] : j.items())
    if (!allowed.contains(key)) fail(source, where + ": unknown key '" + key + "'");
}

/// A bound in messages: 1000000, not 1e+06 or 1000000.0.
std::string show(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.15g", v);
  return text;
}

/// j[key] as a string, `fallback` when absent; a matlas::Error naming `where.key` otherwise
/// (json::value would throw nlohmann's type_error, naming neither the file nor the key).
std::string string_at(const json& j, const char* key, const std::string& fallback, const std::string& source,
                      const std::string& where) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_string()) fail(source, where + key + " must be a string");
  return j[key].get<std::string>();
}

double number(const json& j, const std::string& source, const std::string& where) {
  if (!j.is_number()) fail(source, where + " must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(source, where + " must be finite");
  return v;
}

Vec3 vec3(const json& j, const std::string& source, const std::string& where) {
  if (!j.is_array() || j.size() != 3) fail(source, where + " must be an array of 3 numbers");
  return Vec3(number(j[0], source, where), number(j[1], source, where), number(j[2], source, where));
}

/// A position or extent in the scene: within kMaxSceneCoordinate of the origin in every
/// coordinate (Embree works in single precision and asserts on infinities).
Vec3 point(const json& j, const std::string& source, const std::string& where) {
  const Vec3 v = vec3(j, source, where);
  if (!v.allFinite() || !(v.cwiseAbs().maxCoeff() <= kMaxSceneCoordinate))
    fail(source, where + " must have coordinates within +-" + show(kMaxSceneCoordinate));
  return v;
}

/// A number in [lo, hi] (finite).
double bounded(const json& j, double lo, double hi, const std::string& source, const std::string& where) {
  const double v = number(j, source, where);
  if (!(v >= lo && v <= hi)) fail(source, where + " must be in [" + show(lo) + ", " + show(hi) + "]");
  return v;
}

Rgb rgb(const json& j, const std::string& source, const std::string& where, double max = 1e30) {
  const Vec3 v = vec3(j, source, where);
  if (v.minCoeff() < 0 || v.maxCoeff() > max)
    fail(source, where + " must be in [0, " + (max < 1e29 ? show(max) : std::string("inf")) + "]");
  return v.array();
}

SurfaceSpec parse_surface(const json& j, const std::string& source, const std::string& where) {
  check_keys(j, {"type", "albedo", "specular", "alpha"}, source, where);
  SurfaceSpec s;
  const std::string type = string_at(j, "type", "lambert", source, where + ".");
  if (type == "lambert") s.kind = SurfaceSpec::Kind::lambert;
  else if (type == "ggx") s.kind = SurfaceSpec::Kind::ggx;
  else if (type == "measured") s.kind = SurfaceSpec::Kind::measured;
  else fail(source, where + ".type must be lambert, ggx or measured, not '" + type + "'");
  if (j.contains("albedo")) s.albedo = rgb(j["albedo"], source, where + ".albedo", 1.0);
  if (j.contains("specular")) s.specular = rgb(j["specular"], source, where + ".specular", 1.0);
  if (j.contains("alpha")) {
    s.alpha = number(j["alpha"], source, where + ".alpha");
    if (!(s.alpha >= 1e-3 && s.alpha <= 1.0)) fail(source, where + ".alpha must be in [0.001, 1]");
  }
  return s;
}

ObjectSpec parse_object(const json& j, const std::string& source, const std::string& where) {
  check_keys(j, {"shape", "mesh", "center", "radius", "rotate_y", "rest_on", "corner", "edge1", "edge2", "material", "emission"},
             source, where);
  ObjectSpec o;
  o.shape = string_at(j, "shape", "sphere", source, where + ".");
  if (o.shape != "sphere" && o.shape != "quad" && o.shape != "mesh")
    fail(source, where + ".shape must be sphere, quad or mesh, not '" + o.shape + "'");
  o.mesh = string_at(j, "mesh", "", source, where + ".");
  if (o.shape == "mesh" && o.mesh.empty()) fail(source, where + ": a mesh object needs \"mesh\"");
  if (o.shape == "mesh" && o.mesh == "sphere") o.shape = "sphere";  // the exact sphere
  if (j.contains("center")) o.center = point(j["center"], source, where + ".center");
  if (j.contains("radius")) {
    o.radius = bounded(j["radius"], 0, kMaxSceneCoordinate, source, where + ".radius");
    if (!(o.radius > 0)) fail(source, where + ".radius must be positive");
  }
  if (j.contains("rotate_y")) o.rotate_y = bounded(j["rotate_y"], -kMaxSceneCoordinate, kMaxSceneCoordinate, source, where + ".rotate_y");
  if (j.contains("rest_on"))
    o.rest_on = bounded(j["rest_on"], -kMaxSceneCoordinate, kMaxSceneCoordinate, source, where + ".rest_on");
  if (j.contains("corner")) o.corner = point(j["corner"], source, where + ".corner");
  if (j.contains("edge1")) o.edge1 = point(j["edge1"], source, where + ".edge1");
  if (j.contains("edge2")) o.edge2 = point(j["edge2"], source, where + ".edge2");
  if (o.shape == "quad" && !(o.edge1.cross(o.edge2).norm() > 0)) fail(source, where + ": the quad's edges are parallel");
  if (j.contains("material")) o.surface = parse_surface(j["material"], source, where + ".material");
  if (j.contains("emission")) o.emission = rgb(j["emission"], source, where + ".emission");
  if (o.emission.maxCoeff() > 0 && o.shape == "sphere") fail(source, where + ": spheres cannot emit");
  if (o.emission.maxCoeff() > 0 && o.surface.kind == SurfaceSpec::Kind::measured)
    fail(source, where + ": the measured object cannot emit");
  return o;
}

render::DirectionalLight parse_light(const json& j, const std::string& source, const std::string& where) {
  check_keys(j, {"direction", "irradiance"}, source, where);
  render::DirectionalLight l;
  if (!j.contains("direction")) fail(source, where + ": a light needs \"direction\"");
  l.direction = vec3(j["direction"], source, where + ".direction");
  if (j.contains("irradiance")) l.irradiance = vec3(j["irradiance"], source, where + ".irradiance").array();
  if (const std::string problem = render::light_problem(l, where); !problem.empty()) fail(source, problem);
  return l;
}

json to_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }
json to_json(const Rgb& v) { return json::array({v.x(), v.y(), v.z()}); }

SceneSpec builtin(const char* text, const std::string& object) {
  std::string s = text;
  const std::string key = "\"$object\"";
  s.replace(s.find(key), key.size(), json(object).dump());
  return parse_scene(json::parse(s), "built-in scene");
}

}  // namespace

SceneSpec parse_scene(const json& j, const std::string& source) {
  check_keys(j, {"name", "camera", "environment", "lights", "objects"}, source, "scene");
  SceneSpec s;
  s.name = string_at(j, "name", "scene", source, "");
  if (j.contains("camera")) {
    const json& c = j["camera"];
    check_keys(c, {"position", "target", "fov", "orthographic", "ortho_height"}, source, "camera");
    if (c.contains("position")) s.camera.position = point(c["position"], source, "camera.position");
    if (c.contains("target")) s.camera.target = point(c["target"], source, "camera.target");
    if (c.contains("fov")) s.camera.fov_degrees = number(c["fov"], source, "camera.fov");
    if (c.contains("orthographic")) {
      if (!c["orthographic"].is_boolean()) fail(source, "camera.orthographic must be true or false");
      s.camera.orthographic = c["orthographic"].get<bool>();
    }
    if (c.contains("ortho_height")) s.camera.ortho_height = number(c["ortho_height"], source, "camera.ortho_height");
    if (const std::string problem = render::camera_problem(s.camera, "fov"); !problem.empty()) fail(source, problem);
  }
  if (j.contains("environment")) {
    const json& e = j["environment"];
    check_keys(e, {"map", "constant", "rotation", "intensity", "visible"}, source, "environment");
    s.environment.map = string_at(e, "map", "", source, "environment.");
    if (e.contains("constant")) s.environment.constant = rgb(e["constant"], source, "environment.constant");
    if (e.contains("rotation")) s.environment.rotation = bounded(e["rotation"], -kMaxSceneCoordinate, kMaxSceneCoordinate, source, "environment.rotation");
    if (e.contains("intensity"))
      s.environment.intensity = bounded(e["intensity"], 0, kMaxSceneCoordinate, source, "environment.intensity");
    if (e.contains("visible")) {
      if (!e["visible"].is_boolean()) fail(source, "environment.visible must be true or false");
      s.environment.visible = e["visible"].get<bool>();
    }
  }
  if (j.contains("lights")) {
    if (!j["lights"].is_array()) fail(source, "\"lights\" must be an array");
    for (std::size_t i = 0; i < j["lights"].size(); ++i)
      s.lights.push_back(parse_light(j["lights"][i], source, "lights[" + std::to_string(i) + "]"));
  }
  if (!j.contains("objects") || !j["objects"].is_array() || j["objects"].empty())
    fail(source, "\"objects\" must be a non-empty array");
  int measured = 0;
  for (std::size_t i = 0; i < j["objects"].size(); ++i) {
    s.objects.push_back(parse_object(j["objects"][i], source, "objects[" + std::to_string(i) + "]"));
    if (s.objects.back().surface.kind == SurfaceSpec::Kind::measured) ++measured;
  }
  if (measured > 1) fail(source, "more than one object has the measured material");
  return s;
}

json scene_to_json(const SceneSpec& s) {
  json j;
  j["name"] = s.name;
  j["camera"] = {{"position", to_json(s.camera.position)}, {"target", to_json(s.camera.target)},
                 {"fov", s.camera.fov_degrees}};
  // Perspective cameras keep the keys scene files had before orthographic ones existed.
  if (s.camera.orthographic) j["camera"]["orthographic"] = true;
  if (s.camera.orthographic || s.camera.ortho_height != render::Camera().ortho_height)
    j["camera"]["ortho_height"] = s.camera.ortho_height;
  json env = {{"constant", to_json(s.environment.constant)}, {"rotation", s.environment.rotation},
              {"intensity", s.environment.intensity}};
  if (!s.environment.map.empty()) env["map"] = s.environment.map;
  // Scenes without the keys added later keep the JSON (and the GI bases' keys) they had.
  if (!s.environment.visible) env["visible"] = false;
  j["environment"] = env;
  if (!s.lights.empty()) {
    j["lights"] = json::array();
    for (const render::DirectionalLight& l : s.lights)
      j["lights"].push_back({{"direction", to_json(l.direction)}, {"irradiance", to_json(l.irradiance)}});
  }
  j["objects"] = json::array();
  for (const ObjectSpec& o : s.objects) {
    static const char* kinds[] = {"lambert", "ggx", "measured"};
    json m = {{"type", kinds[static_cast<int>(o.surface.kind)]}, {"albedo", to_json(o.surface.albedo)},
              {"specular", to_json(o.surface.specular)}, {"alpha", o.surface.alpha}};
    json oj = {{"shape", o.shape}, {"center", to_json(o.center)}, {"radius", o.radius}, {"rotate_y", o.rotate_y},
               {"corner", to_json(o.corner)}, {"edge1", to_json(o.edge1)}, {"edge2", to_json(o.edge2)},
               {"material", m}, {"emission", to_json(o.emission)}};
    if (!o.mesh.empty()) oj["mesh"] = o.mesh;
    if (o.rest_on) oj["rest_on"] = *o.rest_on;
    j["objects"].push_back(oj);
  }
  return j;
}

std::vector<std::string> builtin_scenes() { return {"floor", "box"}; }

namespace {

struct View {
  const char* name;
  Vec3 position, target;
  double fov;
};

/// The cameras of a built-in scene; the first is the scene's own.
std::vector<View> builtin_view_list(const std::string& scene) {
  if (scene == "floor")
    return {{"front", Vec3(0, 1.7, 5.6), Vec3(0, 0.85, 0), 34},
            {"side", Vec3(4.4, 1.3, 3.4), Vec3(0, 0.8, 0), 34},
            {"above", Vec3(0, 4.6, 3.4), Vec3(0, 0.5, 0), 36}};
  if (scene == "box")
    return {{"front", Vec3(0, 2, 3.9), Vec3(0, 1.8, 0), 55},
            {"side", Vec3(1.6, 1.6, 3.7), Vec3(-0.4, 1.1, -0.3), 55},
            {"above", Vec3(0, 3.6, 3.2), Vec3(0, 0.8, -0.3), 60}};
  return {};
}

}  // namespace

std::vector<std::string> builtin_views(const std::string& scene) {
  std::vector<std::string> names;
  for (const View& v : builtin_view_list(scene)) names.emplace_back(v.name);
  return names;
}

bool is_scene(const std::string& name_or_path) {
  const auto builtin = builtin_scenes();
  const std::string base = name_or_path.substr(0, name_or_path.find('@'));
  if (std::find(builtin.begin(), builtin.end(), base) != builtin.end()) return true;
  return std::filesystem::path(name_or_path).extension() == ".json";
}

SceneSpec load_scene(const std::string& name_or_path, const std::string& object) {
  if (name_or_path == "floor") return builtin(kFloorScene, object);
  if (name_or_path == "box") return builtin(kBoxScene, object);
  if (const auto at = name_or_path.find('@'); at != std::string::npos && name_or_path.find_first_of("/.") == std::string::npos) {
    const std::string base = name_or_path.substr(0, at), view = name_or_path.substr(at + 1);
    for (const View& v : builtin_view_list(base)) {
      if (view != v.name) continue;
      SceneSpec s = load_scene(base, object);
      s.name = name_or_path;
      s.camera.position = v.position;
      s.camera.target = v.target;
      s.camera.fov_degrees = v.fov;
      return s;
    }
    std::string list;
    for (const auto& n : builtin_views(base)) list += (list.empty() ? "" : ", ") + n;
    throw Error("scene '" + name_or_path + "': unknown view" + (list.empty() ? " (only built-in scenes have views)" : "; views: " + list));
  }
  const std::filesystem::path path(name_or_path);
  if (path.extension() != ".json")
    throw Error("scene '" + name_or_path + "': expected a built-in scene (floor, box) or a .json file");
  const int fd = open_regular_file(path, "a JSON scene file");
  std::string text;
  try {
    const auto size = std::filesystem::file_size(path);
    if (size > (64u << 20)) fail(path.string(), std::to_string(size) + " bytes: too large for a scene file (64 MiB at most)");
    text.resize(size);
    read_exact_at(fd, path, text.data(), text.size(), 0);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    fail(path.string(), std::string("not valid JSON: ") + e.what());
  }
  return parse_scene(j, path.string());
}

}  // namespace matlas::pathtrace
