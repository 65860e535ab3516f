#include "render/camera.h"

#include <cmath>

namespace matlas::render {

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
