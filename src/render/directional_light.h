#pragma once
// A light infinitely far away (a sun): the directional lights of previews (render/scene.h) and of
// GI scenes (pathtrace/scene_spec.h).
#include <string>

#include "brdf/types.h"
#include "render/scene_bounds.h"

namespace matlas::render {

/// Radiance arriving from `direction` (towards the light; renderers normalise it) producing
/// `irradiance` on a surface facing it. A delta light: reflected radiance f * cos(theta) *
/// irradiance where nothing blocks the direction, and no ray ever hits it.
struct DirectionalLight {
  Vec3 direction = Vec3(0, 1, 0);
  Rgb irradiance = Rgb::Constant(1.0);
};

/// What makes a light unusable, as a message naming the field after `name` ("lights[0]
/// .direction must ..."), or "" for a usable one: a direction not finite, beyond
/// kMaxSceneCoordinate or shorter than 1e-6; an irradiance outside [0, kMaxSceneCoordinate].
std::string light_problem(const DirectionalLight& light, const std::string& name);

}  // namespace matlas::render
