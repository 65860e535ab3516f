#pragma once
// The one camera of previews and GI scenes: a pinhole (perspective) or orthographic camera at
// `position` looking at `target`, and the primary ray through a pixel.
//
// Frame: forward f = (target - position) / |target - position|; right r = f x (0, 1, 0)
// normalised; up u = r x f. When f is parallel to +y (|f x y| < 1e-9: looking straight down or
// straight up) r = (1, 0, 0): straight down, u = (0, 0, -1) (the top of the image towards -z);
// straight up, u = (0, 0, 1). This is the limit of a camera slightly on the +z side of its target,
// so the frame turns continuously as such a camera rises over its target.
//
// Ray through image position (px, py) in pixels of a width x height image (top-left origin,
// 0..width, 0..height), a = width / height, sx = (2 px / width - 1) a, sy = 1 - 2 py / height:
//   perspective:  origin = position, dir = normalise(f + r sx t + u sy t), t = tan(fov / 2);
//   orthographic: origin = position + (r sx + u sy) ortho_height / 2, dir = f.
#include <string>
#include <string_view>

#include "brdf/types.h"
#include "render/scene_bounds.h"

namespace matlas::render {

/// Perspective or orthographic camera looking from `position` at `target`, +y up. The default
/// frames the unit sphere of a preview from the front (+z) and slightly above.
struct Camera {
  bool orthographic = false;
  Vec3 position = Vec3(0.0, 0.35, 4.0);
  Vec3 target = Vec3::Zero();
  double fov_degrees = 32.0;     ///< vertical field of view (perspective)
  double ortho_height = 2.3;     ///< height of the view in world units (orthographic)
};

/// What makes a camera unusable, as a message naming the field ("camera.position must be finite,
/// with coordinates within +-1e6"), or "" for a usable one: a position or target not finite or
/// beyond kMaxSceneCoordinate, a target within 1e-6 of the position, a field of view outside
/// (0, 180) degrees, an orthographic height outside (0, kMaxSceneCoordinate]. `fov_key` is the
/// field of view's name in the caller's input ("fov" in scene files).
std::string camera_problem(const Camera& camera, std::string_view fov_key = "fov_degrees");

/// The camera's orthonormal frame (header comment): right x up = -forward.
struct CameraFrame {
  Vec3 right, up, forward;
};

/// The frame of a camera whose target differs from its position.
CameraFrame camera_frame(const Camera& camera);

/// Primary ray through image position (px, py) in pixels of a width x height image (header
/// comment); `dir` is unit length.
void camera_ray(const Camera& camera, double px, double py, int width, int height, Vec3* origin, Vec3* dir);

}  // namespace matlas::render
