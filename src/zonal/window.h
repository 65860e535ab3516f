#pragma once
// Windows over the bands of a truncated rotated-ZH expansion (docs/REALTIME.md, "Windowing").
//
// Shading with bands 0..L' sums sum_l w_l sum_k lambda_l^k E_l(d_lk): band l's term times a
// factor w_l that depends on the bands shown, L', so that a preview with fewer bands is a
// smoother image and not a ringing one (truncation multiplies the spectrum by a box; the box's
// kernel has negative side lobes, which around a small bright light become dark rings that
// clamp to black). The same factors are the uniform uWindow of the browser's shader
// (web/src/realtime-shader.ts computes them with the same formulas):
//
//   none     w_l = 1
//   hann     w_l = cos^2(pi l / (2 (L' + 1)))                        (0 at l = L' + 1)
//   lanczos  w_l = sinc(pi l / (L' + 1)) = sin(x) / x                 (Lanczos sigma factors)
//   gauss    w_l = exp(-l (l + 1) / (2 s^2)), s = (L' + 1) / 2.5      (a heat kernel: positive
//            on the sphere for every L', so a delta never rings below zero)
//   taper    w_l = 1 for l <= h = (L' + 1) / 2, then cos^2(pi (l - h) / (2 (L' + 1 - h))): Hann
//            over the upper half only (the low bands, all a diffuse material has, untouched)
//
// Every window has w_0 = 1: the mean over the sphere (band 0) is kept, so a diffuse material's
// brightness does not change with the window.
#include <string>
#include <vector>

namespace matlas::zonal {

enum class BandWindow { none, hann, lanczos, gauss, taper };

/// w_0..w_shown of a window for bands 0..shown (shown >= 0; matlas::Error otherwise).
std::vector<double> band_window(BandWindow window, int shown);

/// "none", "hann", "lanczos", "gauss", "taper" (matlas::Error naming the valid ones otherwise).
BandWindow parse_band_window(const std::string& name);
const char* band_window_name(BandWindow window);

}  // namespace matlas::zonal
