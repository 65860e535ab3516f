#pragma once
// Environment lighting: a latitude-longitude (equirectangular) radiance map, or a constant
// radiance, with importance sampling proportional to max(r, g, b) * sin(theta) per texel.
//
// World frame: +y is up. Map coordinates (u, v) in [0, 1)^2, v = 0 at the top (+y):
//   theta = pi v, phi = 2 pi (u - 0.5) + rotation,  d = (sin theta cos phi, cos theta, sin theta sin phi).
// The map is piecewise constant per texel (nearest lookup), so eval and pdf agree exactly.
#include <string>

#include "brdf/types.h"
#include "formats/image_io.h"
#include "render/sampling.h"

namespace matlas::render {

class Environment {
public:
  /// Uniform radiance from every direction (sampled uniformly over the sphere).
  static Environment constant(const Rgb& radiance);
  /// A lat-long map scaled by `intensity` and turned by `rotation_degrees` about +y.
  Environment(Image map, double rotation_degrees = 0.0, double intensity = 1.0);
  /// Reads an .exr/.hdr map (matlas::Error naming the file on failure).
  static Environment load(const std::filesystem::path& path, double rotation_degrees = 0.0,
                          double intensity = 1.0);

  /// Radiance arriving from world direction d (unit).
  Rgb eval(const Vec3& d) const;
  /// Bilinearly filtered radiance, for display of the background only (lighting uses eval, whose
  /// piecewise-constant values match the sampling density exactly).
  Rgb eval_smooth(const Vec3& d) const;
  /// A direction drawn with density pdf (per unit solid angle).
  Vec3 sample(double u0, double u1, double* pdf) const;
  /// Density of sample() for direction d.
  double pdf(const Vec3& d) const;

  /// The turn about +y, radians.
  double rotation() const { return rotation_; }
  int width() const { return map_.width; }
  int height() const { return map_.height; }
  /// Whether the radiance is one constant (no map).
  bool is_constant() const { return constant_; }
  /// The map as lit (intensity applied, negatives clamped; empty for a constant environment).
  const Image& map() const { return map_; }
  /// The world direction of map coordinates (u, v) in [0, 1]^2 (the file's header convention).
  Vec3 from_uv(double u, double v) const;

private:
  Environment() = default;
  void to_uv(const Vec3& d, double* u, double* v) const;

  bool constant_ = false;
  Rgb radiance_ = Rgb::Zero();
  Image map_;
  double rotation_ = 0.0;
  Distribution2D distribution_;
};

}  // namespace matlas::render
