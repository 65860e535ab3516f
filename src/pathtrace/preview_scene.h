#pragma once
// A preview's scene (render/scene.h) as a GI scene: one scene for both integrators, the previews'
// direct lighting (render/render.h) and the path tracer (tracer.h; with max_depth 1 it computes
// the same direct lighting, tests/pathtrace/test_preview_scene.cpp).
#include "pathtrace/scene_spec.h"
#include "render/scene.h"

namespace matlas::pathtrace {

/// The GI scene of a preview's description: its camera; its object ("sphere": the exact unit
/// sphere; a mesh: the same file, placed by render::place_object, the previews' placement) as the
/// measured object; with `ground`, a Lambertian quad of `ground_albedo` where
/// render::place_object puts the ground; its environment (map or constant radiance, rotation,
/// intensity; visible unless show_environment is false) and its directional lights. Reads the
/// object's mesh only to place a ground. The result is checked as a scene file is (parse_scene):
/// matlas::Error "scene: KEY ..." for what a scene file could not hold (a ground albedo outside
/// [0, 1], a negative irradiance, a degenerate camera), and naming the file for an unreadable
/// mesh.
SceneSpec preview_scene(const render::SceneDescription& preview);

}  // namespace matlas::pathtrace
