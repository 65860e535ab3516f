#pragma once
// A window per theta_o sample, chosen from the coefficients themselves (docs/REALTIME.md,
// "Window per view angle").
//
// A fixed window over the bands (zonal/window.h) trades accuracy for the absence of rings
// everywhere: Hann removes the rim's rings of a glossy material under small lights, but also
// dims bands 1-8 of every material (a diffuse one under `studio`: 2 % -> 8 % error). Whether a
// truncated slice rings is visible in the slice itself: a BRDF slice is never negative, and the
// truncation's side lobes make its expansion so. So for each theta_o sample the expansion's band
// l is weighted by
//
//     w_l(t) = 1 - t (1 - h_l),   h_l = cos^2(pi l / (2 (L + 1)))   (Hann over bands 0..L)
//
// with the least t in [0, 1] for which the reconstructed slice (expansion and sharp lobes) has no
// value below -floor * m anywhere on the sphere, m the slice's median level: the area-weighted
// median over the upper hemisphere of its Hann reconstruction (mean over channels). Around a
// highlight the eye compares a ring with the level of the slice away from it: the diffuse part
// of a plastic, nearly nothing for a metal (whose rings, seen against a bright light, show as
// stripes over the whole sphere). The reconstruction is linear in t, so its minimum over a grid
// is concave in t: the least t is found by bisection left of the minimum's highest point. t = 0
// keeps the plain truncation (the lobes' fit is exact for it), t = 1 is Hann; where no t reaches
// the floor (a dip the window cannot lift), Hann.
//
// The weights are multiplied into the coefficients (t differs per material and sample), so a
// map point's coefficients stay the same weighted sum of the materials' (a convex sum of slices,
// each above -floor m_i, is above -floor sum w_i m_i). Shading then needs no window at full
// bands (zonal::ShadeSettings::window = none).
#include <vector>

#include <Eigen/Core>

#include "zonal/basis.h"
#include "zonal/coefficients.h"

namespace matlas::zonal {

struct RingLimit {
  double floor = 0.1;    ///< lowest value allowed, in units of the slice's median level
  int theta_rows = 64;   ///< grid rows over theta in [0, pi], even (the whole sphere: shading integrates all of it)
  int phi_columns = 64;  ///< grid columns over phi in [0, pi] (the slice is even in phi)
  /// Throws matlas::Error naming the setting out of range.
  void validate() const;
};

/// The grid's kernel values, computed once for coefficients of one layout (bands, theta_o samples,
/// lobes) and applied to many.
class RingLimiter {
public:
  /// Throws matlas::Error for a bad `limit` or a basis of fewer bands than `layout` has.
  RingLimiter(const ZonalBasis& basis, const ZonalCoefficients& layout, const RingLimit& limit);
  /// Weights every theta_o sample's bands of `c` in place by w_l(t) above; returns t per sample.
  /// `c` must have the layout's bands, samples and lobes (matlas::Error otherwise). Thread-safe.
  std::vector<double> apply(ZonalCoefficients& c) const;

private:
  RingLimit limit_;
  int bands_, theta_o_count_;
  std::vector<double> lobes_;
  std::vector<double> factor_;   ///< per coefficient j: 1 - h_l, the weight's change at t = 1
  Eigen::MatrixXd kernels_;      ///< [point][j]: Y_l^0(d_j . w)
  std::vector<Eigen::MatrixXd> lobe_values_;  ///< per sample: [point][i] Kc_i(w) / mass_i
  std::vector<double> area_;     ///< per upper-hemisphere point: its area weight
};

}  // namespace matlas::zonal
