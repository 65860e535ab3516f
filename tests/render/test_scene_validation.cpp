// The preview scene refuses cameras and lights that would reach Embree as infinities, naming the
// field, before it loads anything.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "render/scene.h"
#include "support/error_of.h"

namespace matlas::render {
namespace {

std::string error_with(const std::function<void(SceneDescription&)>& edit) {
  SceneDescription d;
  edit(d);
  return test::error_of([&] { Scene scene(d); });
}

TEST(SceneValidation, CamerasAndLightsBeyondReasonAreRefusedNamingTheField) {
  // A camera at 1e308 used to trip an assertion inside Embree (SIGABRT) on the first ray.
  EXPECT_EQ(error_with([](SceneDescription& d) { d.camera.position = Vec3(1e308, 0, 0); }),
            "scene: camera.position must be finite, with coordinates within +-1e6");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.camera.position = Vec3(0, -1e308, 0); }),
            "scene: camera.position must be finite, with coordinates within +-1e6");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.camera.target = Vec3(0, 0, std::nan("")); }),
            "scene: camera.target must be finite, with coordinates within +-1e6");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.camera.target = d.camera.position; }),
            "scene: camera.target must differ from camera.position (by 1e-6 at least)");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.camera.fov_degrees = 180; }),
            "scene: camera.fov_degrees must be in (0, 180)");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.camera.ortho_height = std::numeric_limits<double>::infinity(); }),
            "scene: camera.ortho_height must be in (0, 1e6]");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.lights.push_back({Vec3::Zero(), Rgb::Ones()}); }),
            "scene: lights[0].direction must have a length of 1e-6 at least");
  EXPECT_EQ(error_with([](SceneDescription& d) { d.lights.push_back({Vec3(0, 1, 0), Rgb(1, -1, 1)}); }),
            "scene: lights[0].irradiance must be in [0, 1e6]");
  // Refused before the mesh is looked for: the error is the camera's, not a missing file's.
  EXPECT_EQ(error_with([](SceneDescription& d) {
              d.object = "/nonexistent/mesh.obj";
              d.camera.position = Vec3(1e308, 0, 0);
            }),
            "scene: camera.position must be finite, with coordinates within +-1e6");
}

TEST(SceneValidation, CamerasAtTheLimitsRender) {
  SceneDescription d;
  d.camera.position = Vec3(0, 0, 1e6);
  d.camera.fov_degrees = 1e-3;
  const Scene scene(d);
  Vec3 origin, dir;
  scene.camera_ray(8, 8, 16, 16, &origin, &dir);
  const auto hit = scene.intersect(origin, dir);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->position.z(), 1.0, 1e-3);
}

}  // namespace
}  // namespace matlas::render
