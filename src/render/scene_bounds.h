#pragma once
// The bounds of everything placed in a scene, previews and GI alike.

namespace matlas::render {

/// The largest camera coordinate (and orthographic height), light direction coordinate and
/// irradiance a scene accepts; also the bound of path-traced scenes' coordinates, radii, angles
/// and intensities (pathtrace/scene_spec.h). Embree builds in single precision: beyond, scenes
/// lose their precision, and infinities (a camera at 1e308) trip its assertions.
inline constexpr double kMaxSceneCoordinate = 1e6;

}  // namespace matlas::render
