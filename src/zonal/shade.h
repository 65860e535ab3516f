#pragma once
// The CPU reference of real-time rotated-ZH shading (what the browser's fragment shader computes).
//
// At a surface point with normal n and view direction wo (unit, towards the camera), theta_o =
// acos(n . wo), the local frame has z = n and x along wo's tangential part, and
//
//     radiance = sum_{l <= L} sum_{k <= l} lambda_l^k(theta_o) E_l(sin alpha_{l,k} x + cos alpha_{l,k} n),
//
// with lambda interpolated linearly in theta_o and E_l the band-l prefiltered environment.
// Environment lighting only, without shadows (exact for a convex object such as the sphere).
#include "formats/image_io.h"
#include "render/scene.h"
#include "zonal/basis.h"
#include "zonal/coefficients.h"
#include "zonal/light_split.h"
#include "zonal/prefilter.h"
#include "zonal/window.h"

namespace matlas::zonal {

/// Radiance leaving a point of normal n towards wo (world, unit vectors). With `window`
/// (zonal/window.h: w_0..w_L'), only bands 0..L' are summed, band l's terms times w_l; without
/// it every band of the coefficients, unweighted.
Rgb shade_point(const ZonalBasis& basis, const ZonalCoefficients& c, const PrefilteredEnvironment& env,
                const Vec3& n, const Vec3& wo, const std::vector<double>* window = nullptr);

struct ShadeSettings {
  int width = 256;
  int height = 256;
  int subsamples = 2;  ///< per axis: subsamples^2 stratified rays per pixel, averaged
  /// Bands shown, L' (-1: all of the coefficients'), and the window over them (zonal/window.h):
  /// `window` when every band is shown (none: the lobes were fitted against exactly this
  /// truncation, so the pair is consistent), `reduced_window` for a preview with fewer bands
  /// (L' < L: the residual's bands above L' are missing, and a window keeps it from ringing).
  int shown_bands = -1;
  BandWindow window = BandWindow::none;
  BandWindow reduced_window = BandWindow::hann;
};

/// The scene's object shaded with the coefficients under the prefiltered environment, through
/// the scene's camera (same rays as render::render); pixels missing the object show the
/// environment (Environment::eval_smooth) or black, as the renderer does. Throws matlas::Error
/// for scenes with a ground plane or directional lights, which this shading does not model.
/// With `lights` (zonal/light_split.h: `env` prefiltered from the split's residual), each point
/// adds the split's light points shaded with `lights->material`.
struct DirectLights {
  const std::vector<LightPoint>* points = nullptr;
  const render::Material* material = nullptr;
};
Image shade_image(const render::Scene& scene, const ZonalBasis& basis, const ZonalCoefficients& c,
                  const PrefilteredEnvironment& env, const ShadeSettings& settings,
                  const DirectLights* lights = nullptr);

}  // namespace matlas::zonal
