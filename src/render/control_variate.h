#pragma once
// A control variate for the renderer's object (render/render.h).
//
// g(wi, wo) approximates the cosine-weighted slice f(wi, wo) max(cos theta_i, 0) of the object's
// material over the WHOLE sphere of incident directions, and its integral against the environment,
// G(n, wo) = integral_S L(w) g(w) dw, is known without sampling (zonal/control_variate.h: the
// real-time rotated-ZH shading). With one, every camera sample at the object estimates
//
//     I = G + integral_S L(w) (V(w) f(w, wo) max(cos theta, 0) - g(w)) dw
//
// with its own taps and weights: unbiased whatever g is (below the horizon only the environment
// technique samples, and alone it counts there; the lobe technique's directions below the horizon
// count for nothing, as they do for f), and with less variance the closer g is to the slice. G is
// exact only as far as its tabulation is (what the caller measures). g is one material's, so only
// render() of one material takes one: render_bank's images stay linear in the BRDF.
#include "brdf/types.h"

namespace matlas::render {

class ControlVariate {
public:
  virtual ~ControlVariate() = default;
  /// G = smooth + sharp for a surface point of normal n seen from wo (world, unit, n . wo > 0).
  /// The smooth part varies slowly over the image (band-limited), so the renderer may tabulate
  /// it at pixel corners and interpolate (ControlGrid); the sharp part is evaluated at every
  /// camera sample.
  virtual Rgb smooth_integral(const Vec3& n, const Vec3& wo) const = 0;
  virtual Rgb sharp_integral(const Vec3& n, const Vec3& wo) const = 0;
  Rgb integral(const Vec3& n, const Vec3& wo) const { return smooth_integral(n, wo) + sharp_integral(n, wo); }
  /// g(wi, wo) in a local frame (z the normal, any tangent), wo.z > 0, wi anywhere on the sphere.
  virtual Rgb eval(const Vec3& wi, const Vec3& wo) const = 0;
};

}  // namespace matlas::render
