#pragma once
// An environment split into its brightest texels, shaded directly with the BRDF, and the rest,
// shaded by the zonal expansion. A map of a few very small, very bright lights (the `studio`
// softboxes, a sun) puts most of a glossy sphere's radiance into highlights that the expansion's
// bands and symmetric lobes only approximate (stretched at grazing angles, sharper than the
// sharpest lobe); the same lights as points evaluated with the BRDF itself are exact to the
// texel, and what is left is dim and smooth, where the expansion is accurate.
//
// The split is exact: residual + lights = the map, texel for texel (the residual's texels that
// became lights are 0). Each light texel is one point at its centre, carrying its radiance times
// its exact solid angle.

#include <vector>

#include "brdf/types.h"
#include "render/environment.h"
#include "render/material.h"

namespace matlas::zonal {

struct LightSplitSettings {
  /// At most this many texels (blocks, with `merge`) become lights (the brightest by luminance).
  int max_texels = 1024;
  /// Only texels at least `ratio` times the map's mean luminance radiance (over the sphere).
  double ratio = 8.0;
  /// Texels per block side: the map is split by blocks of merge x merge texels, each block
  /// chosen as a whole and shaded as one point (its power-weighted mean direction, its total
  /// power); 1: texel by texel.
  int merge = 1;
};

/// One point of a light texel: its world direction and radiance times solid angle (irradiance
/// at normal incidence).
struct LightPoint {
  Vec3 direction;
  Rgb power;
};

struct LightSplit {
  render::Environment residual;
  std::vector<LightPoint> points;
  int texels = 0;                ///< texels moved to the lights
  double light_fraction = 0.0;   ///< their share of the map's luminance integral over the sphere
};

/// Throws matlas::Error for settings out of range. A constant environment has no lights.
LightSplit split_lights(const render::Environment& env, const LightSplitSettings& settings);

/// sum over the points of f(wi, wo) power max(0, n . wi), with f the material in the local
/// frame of n (render's convention: z = n).
Rgb shade_lights(const std::vector<LightPoint>& points, const render::Material& material, const Vec3& n,
                 const Vec3& wo);

}  // namespace matlas::zonal
