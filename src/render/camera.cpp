#include "render/camera.h"

#include <cmath>

namespace matlas::render {

std::string camera_problem(const Camera& c, std::string_view fov_key) {
  const auto bad_point = [](const Vec3& v) {
    return !v.allFinite() || !(v.cwiseAbs().maxCoeff() <= kMaxSceneCoordinate);  // maxCoeff may skip a NaN
  };
  if (bad_point(c.position)) return "camera.position must be finite, with coordinates within +-1e6";
  if (bad_point(c.target)) return "camera.target must be finite, with coordinates within +-1e6";
  if (!((c.target - c.position).norm() >= 1e-6)) return "camera.target must differ from camera.position (by 1e-6 at least)";
  if (!(c.fov_degrees > 0 && c.fov_degrees < 180)) return "camera." + std::string(fov_key) + " must be in (0, 180)";
  if (!(c.ortho_height > 0 && c.ortho_height <= kMaxSceneCoordinate)) return "camera.ortho_height must be in (0, 1e6]";
  return {};
}

CameraFrame camera_frame(const Camera& c) {
  CameraFrame f;
  f.forward = (c.target - c.position).normalized();
  f.right = f.forward.cross(Vec3(0, 1, 0));
  if (f.right.norm() < 1e-9) f.right = Vec3(1, 0, 0);
  f.right.normalize();
  f.up = f.right.cross(f.forward);
  return f;
}

void camera_ray(const Camera& c, double px, double py, int width, int height, Vec3* origin, Vec3* dir) {
  const CameraFrame f = camera_frame(c);
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  const double sx = (2.0 * px / width - 1.0) * aspect;
  const double sy = 1.0 - 2.0 * py / height;
  if (c.orthographic) {
    const double half = 0.5 * c.ortho_height;
    *origin = c.position + f.right * (sx * half) + f.up * (sy * half);
    *dir = f.forward;
  } else {
    const double t = std::tan(0.5 * c.fov_degrees * kPi / 180.0);
    *origin = c.position;
    *dir = (f.forward + f.right * (sx * t) + f.up * (sy * t)).normalized();
  }
}

}  // namespace matlas::render
