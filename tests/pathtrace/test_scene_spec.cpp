// JSON scene files against hostile values: wrong types and absurd magnitudes are matlas::Errors
// naming the file and the key, before anything reaches Embree.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/world.h"
#include "render/scene.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas::pathtrace {
namespace {

using nlohmann::json;

json minimal_scene() {
  return {{"camera", {{"position", {0, 1, 5}}, {"target", {0, 0, 0}}, {"fov", 40}}},
          {"objects", json::array({{{"shape", "sphere"}, {"material", {{"type", "measured"}}}},
                                   {{"shape", "quad"}, {"corner", {-2, -1, -2}}, {"edge1", {0, 0, 4}},
                                    {"edge2", {4, 0, 0}}}})}};
}

/// The error of parsing the minimal scene edited by `edit`, as file "s.json".
template <class Edit>
std::string error_with(Edit edit) {
  json j = minimal_scene();
  edit(j);
  return test::error_of([&] { parse_scene(j, "s.json"); });
}

TEST(SceneSpec, WrongTypesNameTheFileAndTheKey) {
  // Each used to escape as nlohmann's "[json.exception.type_error.302] type must be string, but
  // is number", naming neither the file nor the key (printed as an internal error).
  EXPECT_EQ(error_with([](json& j) { j["name"] = 5; }), "s.json: name must be a string");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0]["shape"] = 1.5; }), "s.json: objects[0].shape must be a string");
  EXPECT_EQ(error_with([](json& j) { j["objects"][1]["material"] = {{"type", json::array()}}; }),
            "s.json: objects[1].material.type must be a string");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0]["mesh"] = true; }), "s.json: objects[0].mesh must be a string");
  EXPECT_EQ(error_with([](json& j) { j["environment"] = {{"map", 3}}; }), "s.json: environment.map must be a string");
  EXPECT_EQ(error_with([](json& j) { j["camera"]["fov"] = "wide"; }), "s.json: camera.fov must be a number");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0]["radius"] = json::object(); }),
            "s.json: objects[0].radius must be a number");
  EXPECT_EQ(error_with([](json& j) { j["objects"][1]["corner"] = "here"; }),
            "s.json: objects[1].corner must be an array of 3 numbers");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0] = 7; }), "s.json: objects[0] must be an object");
  EXPECT_EQ(error_with([](json& j) { j["camera"] = json::array(); }), "s.json: camera must be an object");
}

TEST(SceneSpec, AbsurdMagnitudesAreRefusedNamingTheKey) {
  // A camera at 1e308 reached Embree as infinities (float) and tripped its assertion: SIGABRT.
  EXPECT_EQ(error_with([](json& j) { j["camera"]["position"] = {1e308, 0, 0}; }),
            "s.json: camera.position must have coordinates within +-1000000");
  EXPECT_EQ(error_with([](json& j) { j["camera"]["target"] = {0, -1e308, 0}; }),
            "s.json: camera.target must have coordinates within +-1000000");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0]["center"] = {0, 0, 2e6}; }),
            "s.json: objects[0].center must have coordinates within +-1000000");
  EXPECT_EQ(error_with([](json& j) { j["objects"][1]["edge2"] = {1e300, 0, 0}; }),
            "s.json: objects[1].edge2 must have coordinates within +-1000000");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0]["radius"] = 1e300; }),
            "s.json: objects[0].radius must be in [0, 1000000]");
  EXPECT_EQ(error_with([](json& j) { j["objects"][0]["rest_on"] = -1e20; }),
            "s.json: objects[0].rest_on must be in [-1000000, 1000000]");
  EXPECT_EQ(error_with([](json& j) { j["environment"] = {{"intensity", 1e308}}; }),
            "s.json: environment.intensity must be in [0, 1000000]");
  // A degenerate look-at: the target within 1e-6 of the position (a difference that is 0, or
  // that underflows when normalised).
  EXPECT_EQ(error_with([](json& j) { j["camera"]["target"] = {0, 1, 5 + 1e-9}; }),
            "s.json: camera.target must differ from camera.position (by 1e-6 at least)");
  // At the limits, the scene parses and Embree builds it.
  json j = minimal_scene();
  j["camera"]["position"] = {1e6, -1e6, 1e6};
  j["objects"][0]["center"] = {-1e6, 0, 0};
  j["objects"][0]["radius"] = 1e6;
  const SceneSpec spec = parse_scene(j, "s.json");
  const World world(spec);
  EXPECT_TRUE(world.intersect(Vec3(-1e6, 0, 5e6), Vec3(0, 0, -1)).has_value());
}

TEST(SceneSpec, SceneFilesNameThemselvesInErrors) {
  const test::TempDir dir("matlas-scene-spec");
  json j = minimal_scene();
  j["camera"]["position"] = {0, 1e308, 0};
  write_file_atomic(dir / "far.json", j.dump());
  const std::string e = test::error_of([&] { load_scene((dir / "far.json").string()); });
  EXPECT_EQ(e, (dir / "far.json").string() + ": camera.position must have coordinates within +-1000000");
}

TEST(SceneSpec, CameraKeysRoundTripAndOldFilesKeepTheirKeys) {
  // A scene file written before orthographic cameras: read as it was, written with the same keys.
  const SceneSpec old = parse_scene(minimal_scene(), "s.json");
  EXPECT_FALSE(old.camera.orthographic);
  EXPECT_EQ(old.camera.fov_degrees, 40.0);
  EXPECT_EQ(scene_to_json(old)["camera"], json({{"position", {0.0, 1.0, 5.0}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 40.0}}));
  // Without a camera: at (0, 1, 5), 35 degrees, looking at the origin.
  json no_camera = minimal_scene();
  no_camera.erase("camera");
  const SceneSpec d = parse_scene(no_camera, "s.json");
  EXPECT_EQ(d.camera.position, Vec3(0, 1, 5));
  EXPECT_EQ(d.camera.target, Vec3::Zero());
  EXPECT_EQ(d.camera.fov_degrees, 35.0);
  // Orthographic cameras: optional keys, round trip.
  json ortho = minimal_scene();
  ortho["camera"]["orthographic"] = true;
  ortho["camera"]["ortho_height"] = 3.5;
  const SceneSpec o = parse_scene(ortho, "s.json");
  EXPECT_TRUE(o.camera.orthographic);
  EXPECT_EQ(o.camera.ortho_height, 3.5);
  const SceneSpec back = parse_scene(scene_to_json(o), "again");
  EXPECT_TRUE(back.camera.orthographic);
  EXPECT_EQ(back.camera.ortho_height, 3.5);
  EXPECT_EQ(scene_to_json(back), scene_to_json(o));
  EXPECT_EQ(error_with([](json& j) { j["camera"]["orthographic"] = 1; }), "s.json: camera.orthographic must be true or false");
  EXPECT_EQ(error_with([](json& j) { j["camera"]["ortho_height"] = 0; }), "s.json: camera.ortho_height must be in (0, 1e6]");
  EXPECT_EQ(error_with([](json& j) { j["camera"]["ortho_height"] = 1e9; }),
            "s.json: camera.ortho_height must be in (0, 1e6]");
}

TEST(SceneSpec, LightsAndAnInvisibleEnvironmentRoundTripAndOldFilesKeepTheirKeys) {
  // Without the keys: no lights, a visible environment, and the JSON without them (GI bases'
  // keys of earlier scenes unchanged).
  const SceneSpec old = parse_scene(minimal_scene(), "s.json");
  EXPECT_TRUE(old.lights.empty());
  EXPECT_TRUE(old.environment.visible);
  EXPECT_FALSE(scene_to_json(old).contains("lights"));
  EXPECT_FALSE(scene_to_json(old)["environment"].contains("visible"));
  json file = minimal_scene();
  file["environment"] = {{"constant", {0.5, 0.5, 0.5}}, {"visible", false}};
  file["lights"] = {{{"direction", {1, 2, 0.5}}, {"irradiance", {3, 2.5, 2}}}, {{"direction", {0, 0, -4}}}};
  const SceneSpec s = parse_scene(file, "s.json");
  EXPECT_FALSE(s.environment.visible);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].direction, Vec3(1, 2, 0.5));
  EXPECT_EQ(s.lights[0].irradiance.matrix(), Vec3(3, 2.5, 2));
  EXPECT_EQ(s.lights[1].irradiance.matrix(), Vec3(1, 1, 1));  // the default: 1 on a surface facing it
  const SceneSpec back = parse_scene(scene_to_json(s), "again");
  EXPECT_FALSE(back.environment.visible);
  ASSERT_EQ(back.lights.size(), 2u);
  EXPECT_EQ(back.lights[1].direction, Vec3(0, 0, -4));
  EXPECT_EQ(scene_to_json(back), scene_to_json(s));
  // The world keeps the lights that give light, their directions normalised.
  const World world(s);
  ASSERT_EQ(world.directional_lights().size(), 2u);
  EXPECT_NEAR((world.directional_lights()[1].direction - Vec3(0, 0, -1)).norm(), 0.0, 1e-15);

  EXPECT_EQ(error_with([](json& j) { j["lights"] = json::array({1.5}); }), "s.json: lights[0] must be an object");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = 3; }), "s.json: \"lights\" must be an array");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = {{{"irradiance", {1, 1, 1}}}}; }),
            "s.json: lights[0]: a light needs \"direction\"");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = {{{"direction", {0, 1, 0}}, {"colour", 1}}}; }),
            "s.json: lights[0]: unknown key 'colour'");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = {{{"direction", {0, 0, 0}}}}; }),
            "s.json: lights[0].direction must have a length of 1e-6 at least");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = {{{"direction", {0, 1e300, 0}}}}; }),
            "s.json: lights[0].direction must be finite, with coordinates within +-1e6");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = {{{"direction", {0, 1, 0}}, {"irradiance", {1, -1, 1}}}}; }),
            "s.json: lights[0].irradiance must be in [0, 1e6]");
  EXPECT_EQ(error_with([](json& j) { j["lights"] = {{{"direction", {0, 1, 0}}, {"irradiance", {1, 1e7, 1}}}}; }),
            "s.json: lights[0].irradiance must be in [0, 1e6]");
  EXPECT_EQ(error_with([](json& j) { j["environment"] = {{"visible", "no"}}; }),
            "s.json: environment.visible must be true or false");
  EXPECT_EQ(error_with([](json& j) { j["objects"][1]["material"] = {{"albedo", {2, 0, 0}}}; }),
            "s.json: objects[1].material.albedo must be in [0, 1]");
}

TEST(SceneSpec, GiAndPreviewsShareTheCameraRays) {
  // The same camera gives the same rays, bit for bit, in a GI world and a preview scene; straight
  // down too (the top of the image towards -z).
  for (const Vec3& position : {Vec3(0, 1, 5), Vec3(0, 6, 0), Vec3(0, -6, 0), Vec3(2, 3, -4)}) {
    json j = minimal_scene();
    j["camera"]["position"] = {position.x(), position.y(), position.z()};
    for (const bool orthographic : {false, true}) {
      j["camera"]["orthographic"] = orthographic;
      const World world(parse_scene(j, "s.json"));
      render::SceneDescription d;
      d.camera = world.spec().camera;
      const render::Scene scene(d, std::nullopt, render::Environment::constant(Rgb::Ones()));
      for (const auto& [px, py] : {std::pair{0.5, 0.5}, {20.0, 12.0}, {31.5, 23.5}}) {
        Vec3 o1, d1, o2, d2;
        world.camera_ray(px, py, 32, 24, &o1, &d1);
        scene.camera_ray(px, py, 32, 24, &o2, &d2);
        EXPECT_EQ(o1, o2);
        EXPECT_EQ(d1, d2);
        EXPECT_NEAR(d1.norm(), 1.0, 1e-12);
      }
    }
  }
  json down = minimal_scene();
  down["camera"]["position"] = {0, 6, 0};
  const World world(parse_scene(down, "s.json"));
  Vec3 origin, dir;
  world.camera_ray(16, 0, 32, 32, &origin, &dir);  // the top row looks towards -z
  EXPECT_LT(dir.z(), -0.1);
  EXPECT_NEAR(dir.x(), 0.0, 1e-12);
  world.camera_ray(16, 16, 32, 32, &origin, &dir);
  const auto hit = world.intersect(origin, dir);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->object, 0);
  EXPECT_LT((hit->position - Vec3(0, 1, 0)).norm(), 1e-9);
}

}  // namespace
}  // namespace matlas::pathtrace
