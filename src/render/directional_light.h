#pragma once
// A light infinitely far away (a sun): the directional lights of previews (render/scene.h) and of
// GI scenes (pathtrace/scene_spec.h).
#include "brdf/types.h"

namespace matlas::render {

/// Radiance arriving from `direction` (towards the light; renderers normalise it) producing
/// `irradiance` on a surface facing it. A delta light: reflected radiance f * cos(theta) *
/// irradiance where nothing blocks the direction, and no ray ever hits it.
struct DirectionalLight {
  Vec3 direction = Vec3(0, 1, 0);
  Rgb irradiance = Rgb::Constant(1.0);
};

}  // namespace matlas::render
