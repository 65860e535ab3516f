// The one camera of previews and GI: its frame (with the fallback of a camera looking straight
// down or up) and its rays, against a computation from yaw and pitch angles.
#include <gtest/gtest.h>

#include <cmath>

#include "render/camera.h"
#include "render/scene.h"

namespace matlas::render {
namespace {

void expect_near(const Vec3& a, const Vec3& b, double tol) {
  EXPECT_LT((a - b).norm(), tol) << a.transpose() << " vs " << b.transpose();
}

void expect_orthonormal(const CameraFrame& f) {
  EXPECT_NEAR(f.right.norm(), 1.0, 1e-12);
  EXPECT_NEAR(f.up.norm(), 1.0, 1e-12);
  EXPECT_NEAR(f.forward.norm(), 1.0, 1e-12);
  EXPECT_NEAR(f.right.dot(f.up), 0.0, 1e-12);
  EXPECT_NEAR(f.right.dot(f.forward), 0.0, 1e-12);
  EXPECT_NEAR(f.up.dot(f.forward), 0.0, 1e-12);
  expect_near(f.right.cross(f.up), -f.forward, 1e-12);  // right-handed, looking down -z locally
}

Camera looking(const Vec3& position, const Vec3& target, double fov = 40.0) {
  Camera c;
  c.position = position;
  c.target = target;
  c.fov_degrees = fov;
  return c;
}

TEST(Camera, StraightDownAndUpHaveOneFrameThatIsTheLimitOfACameraInFront) {
  const CameraFrame down = camera_frame(looking(Vec3(0, 5, 0), Vec3::Zero()));
  expect_orthonormal(down);
  expect_near(down.forward, Vec3(0, -1, 0), 1e-15);
  expect_near(down.right, Vec3(1, 0, 0), 1e-15);
  expect_near(down.up, Vec3(0, 0, -1), 1e-15);
  const CameraFrame up = camera_frame(looking(Vec3(0, -5, 0), Vec3::Zero()));
  expect_orthonormal(up);
  expect_near(up.right, Vec3(1, 0, 0), 1e-15);
  expect_near(up.up, Vec3(0, 0, 1), 1e-15);
  // A camera slightly in front (+z) of its target, above or below it, has nearly that frame.
  for (const double eps : {1e-3, 1e-6, 1e-8}) {
    const CameraFrame d = camera_frame(looking(Vec3(0, 5, 5 * eps), Vec3::Zero()));
    expect_orthonormal(d);
    expect_near(d.right, down.right, 1e-12);
    expect_near(d.up, down.up, 2 * eps);
    const CameraFrame u = camera_frame(looking(Vec3(0, -5, 5 * eps), Vec3::Zero()));
    expect_near(u.right, up.right, 1e-12);
    expect_near(u.up, up.up, 2 * eps);
  }
}

TEST(Camera, PerspectiveRaysMatchARotationByYawAndPitch) {
  // Independently: a camera looking down -z, turned by pitch about x and then by yaw about y.
  const int width = 64, height = 48;
  for (const Camera& c : {looking(Vec3(1, 2, 3), Vec3(0, 0.5, 0), 40.0), looking(Vec3(-4, 0.2, -1), Vec3(0.5, 1, 2), 75.0),
                          looking(Vec3(0, 1, 5), Vec3::Zero(), 35.0), looking(Vec3(0.3, 9, 0.1), Vec3::Zero(), 20.0)}) {
    const Vec3 f = (c.target - c.position).normalized();
    const double yaw = std::atan2(-f.x(), -f.z()), pitch = std::asin(f.y());
    const auto rotate = [&](const Vec3& v) {
      const Vec3 p(v.x(), v.y() * std::cos(pitch) - v.z() * std::sin(pitch), v.y() * std::sin(pitch) + v.z() * std::cos(pitch));
      return Vec3(p.x() * std::cos(yaw) + p.z() * std::sin(yaw), p.y(), -p.x() * std::sin(yaw) + p.z() * std::cos(yaw));
    };
    const double t = std::tan(0.5 * c.fov_degrees * kPi / 180.0), aspect = double(width) / height;
    for (const auto& [px, py] : {std::pair{32.0, 24.0}, {0.0, 0.0}, {64.0, 48.0}, {10.5, 40.25}, {63.5, 0.5}}) {
      Vec3 origin, dir;
      camera_ray(c, px, py, width, height, &origin, &dir);
      const Vec3 local((2 * px / width - 1) * aspect * t, (1 - 2 * py / height) * t, -1.0);
      EXPECT_EQ(origin, c.position);
      expect_near(dir, rotate(local).normalized(), 1e-12);
    }
  }
}

TEST(Camera, OrthographicRaysAreParallelAndSpanTheHeight) {
  Camera c = looking(Vec3(0, 0, 5), Vec3::Zero());
  c.orthographic = true;
  c.ortho_height = 2.0;
  Vec3 origin, dir;
  camera_ray(c, 0.0, 0.0, 40, 20, &origin, &dir);  // top-left corner: x = -aspect, y = +1
  expect_near(origin, Vec3(-2, 1, 5), 1e-15);
  expect_near(dir, Vec3(0, 0, -1), 1e-15);
  camera_ray(c, 40.0, 20.0, 40, 20, &origin, &dir);
  expect_near(origin, Vec3(2, -1, 5), 1e-15);
  expect_near(dir, Vec3(0, 0, -1), 1e-15);
}

TEST(Camera, AStraightDownPreviewSeesTheTopOfTheSphereWithTheImageTopTowardsMinusZ) {
  SceneDescription d;
  d.camera = looking(Vec3(0, 4, 0), Vec3::Zero(), 30.0);
  const Scene scene(d, std::nullopt, Environment::constant(Rgb::Ones()));
  Vec3 origin, dir;
  scene.camera_ray(16, 16, 32, 32, &origin, &dir);
  const auto centre = scene.intersect(origin, dir);
  ASSERT_TRUE(centre.has_value());
  expect_near(centre->position, Vec3(0, 1, 0), 1e-9);
  expect_near(centre->normal, Vec3(0, 1, 0), 1e-9);
  scene.camera_ray(16, 8, 32, 32, &origin, &dir);  // above the centre of the image
  const auto top = scene.intersect(origin, dir);
  ASSERT_TRUE(top.has_value());
  EXPECT_LT(top->position.z(), -0.1);
  EXPECT_NEAR(top->position.x(), 0.0, 1e-9);
  scene.camera_ray(24, 16, 32, 32, &origin, &dir);  // right of the centre
  EXPECT_GT(dir.x(), 0.1);
  EXPECT_NEAR(dir.z(), 0.0, 1e-12);
}

TEST(Camera, ProblemsAreNamedOnceForPreviewsAndSceneFiles) {
  EXPECT_EQ(camera_problem(Camera{}), "");
  const auto with = [](auto change) {
    Camera c;
    change(c);
    return c;
  };
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.position.x() = 2e6; })),
            "camera.position must be finite, with coordinates within +-1e6");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.target.y() = std::nan(""); })),
            "camera.target must be finite, with coordinates within +-1e6");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.target = c.position + Vec3(0, 0, 1e-7); })),
            "camera.target must differ from camera.position (by 1e-6 at least)");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.fov_degrees = 0; })), "camera.fov_degrees must be in (0, 180)");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.fov_degrees = 180; }), "fov"), "camera.fov must be in (0, 180)");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.ortho_height = 0; })), "camera.ortho_height must be in (0, 1e6]");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.ortho_height = 1.5e6; })), "camera.ortho_height must be in (0, 1e6]");
  EXPECT_EQ(camera_problem(with([](Camera& c) { c.position = Vec3(0, 0, 1e6); c.fov_degrees = 1e-3; })), "");
}

}  // namespace
}  // namespace matlas::render
