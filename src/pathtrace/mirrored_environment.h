#pragma once
// MirroredEnvironment: the environment seen in the scene's glossy planes, as a sampling strategy
// for the direction a path takes from a vertex (docs/GI.md, "Light reflected by the floor").
//
// A glossy floor (a GGX quad of small alpha) shows the environment's bright parts mirrored below
// it, and what a diffuse wall or the object receives from those mirror images is a caustic: a path
// from the wall finds it only when its cosine-sampled direction happens to hit the floor where the
// floor reflects a softbox, as rarely as it would hit the softbox itself without next-event
// estimation. This strategy draws a direction d from the environment's own density and takes its
// mirror image in the plane of one of the glossy quads, R(d) = d - 2 (d . n) n, the direction in
// which a path meets that plane's reflection of d. R is a reflection, so it keeps solid angle:
// the density of R(d) at w is the environment's density at R(w). The path tracer mixes it with the
// surface's own density (one-sample mixture, probability `probability`):
//
//     p(w) = (1 - P) p_surface(w) + P / |M| sum over planes m in M of p_env(R_m(w)),
//
// M the glossy quads other than the vertex's own object; with no environment or no such plane
// P = 0. Everything here depends on the scene's geometry and the environment only, never on the
// measured material, so the image stays affine in the table (I = P + N z + I2).
#include <vector>

#include "pathtrace/world.h"

namespace matlas::pathtrace {

/// A quad is a mirror plane of the strategy when it is a GGX surface with a specular part and
/// alpha at most this (rougher planes blur the environment's mirror images: a surface's own
/// sampling and next-event estimation find that light).
inline constexpr double kMirrorPlaneMaxAlpha = 0.3;

class MirroredEnvironment {
public:
  /// The glossy quads of `world` (none without an environment). The world must outlive this.
  MirroredEnvironment(const World& world, double probability);

  /// The probability of the strategy at a vertex on `object` (0 when no plane but the object's own).
  double probability(int object) const;
  /// Draws a direction (world) for a vertex on `object`, given that the strategy was chosen:
  /// `u_plane` in [0, 1) picks the plane, (u0, u1) the environment's direction. Requires
  /// probability(object) > 0.
  Vec3 sample(int object, double u_plane, double u0, double u1) const;
  /// The strategy's own density at world direction w for a vertex on `object` (without the
  /// mixture's probability): the mean over the planes of the environment's density at R_m(w).
  double pdf(int object, const Vec3& w) const;

  /// The mirror planes' unit normals and objects (for tests and docs).
  struct Plane {
    int object = -1;
    Vec3 normal;
  };
  const std::vector<Plane>& planes() const { return planes_; }

private:
  /// The planes usable from a vertex on `object`: all but its own.
  int usable(int object) const;

  const World& world_;
  double probability_ = 0;
  std::vector<Plane> planes_;
};

/// w mirrored in a plane of unit normal n: w - 2 (w . n) n.
inline Vec3 mirror(const Vec3& w, const Vec3& n) { return w - 2.0 * w.dot(n) * n; }

}  // namespace matlas::pathtrace
