#pragma once
// The real-time rotated-ZH shading as a control variate of the path-traced preview
// (render/control_variate.h; docs/RENDERING.md "Control variate").
//
// The zonal coefficients of a material (zonal/projection.h) define, per theta_o, a function over
// the whole sphere: the slice's rotated-ZH expansion (written here in the even real harmonics of
// the slice's frame, a_l = A_l lambda_l, zonal/basis.h) plus the sharp lobes as plain lobes
// lambda_i K_i(r . w) (the stored weight is c_i mass_i; without the cosine, so that the lobe's
// integral against the environment is exactly the lobe map's E_i(r)). Its integral against the
// environment is then what the real-time shading computes, sum_{l,k} lambda_l^k E_l(d_{l,k}) +
// sum_i lambda_i E_i(r) (zonal/shade.h), read from the prefiltered maps. The renderer samples the
// difference between the material and this function; the maps' interpolation is the only bias.
#include <memory>
#include <vector>

#include "render/control_variate.h"
#include "zonal/basis.h"
#include "zonal/coefficients.h"
#include "zonal/prefilter.h"
#include "zonal/projection.h"
#include "zonal/sh.h"

namespace matlas::zonal {

/// The projection of a control variate's coefficients: 16 bands, 32 theta_o samples, the default
/// lobes (what the real-time view uses).
ProjectionSettings control_projection_settings();
/// The environment of a control variate: as the real-time view's, with maps fine enough that
/// their bilinear reads, G's only bias, stay near 0.05 % (32 texels per band; the sharpest lobe on
/// 1025 rows, the others in proportion: docs/RENDERING.md "Control variate").
PrefilterSettings control_prefilter_settings();

class ZonalControlVariate final : public render::ControlVariate {
public:
  /// `lobes`: how many of the coefficients' lobes (the broadest first) take part (-1: all).
  /// Throws matlas::Error for layouts that do not match.
  ZonalControlVariate(const ZonalCoefficients& coefficients, std::shared_ptr<const PrefilteredEnvironment> environment,
                      int lobes = -1);

  /// The expansion's part (sum_{l,k} lambda_l^k E_l(d_{l,k})): band-limited, smooth.
  Rgb smooth_integral(const Vec3& n, const Vec3& wo) const override;
  /// The lobes' part (sum_i lambda_i E_i(r)).
  Rgb sharp_integral(const Vec3& n, const Vec3& wo) const override;
  Rgb eval(const Vec3& wi, const Vec3& wo) const override;

private:
  ZonalCoefficients coefficients_;
  ZonalBasis basis_;
  std::shared_ptr<const PrefilteredEnvironment> keep_;
  const PrefilteredEnvironment& environment_;
  std::size_t lobes_;
  LegendreRecurrence legendre_;
  std::vector<double> sin_alpha_, cos_alpha_;  ///< of each rotated-ZH direction d_{l,k}
  /// Per theta_o sample t: the even SH coefficients a_lm of the expansion (m = 0..l, lm_index),
  /// RGB interleaved, then the lobe weights: [t][(lm or K + i) * 3 + c].
  std::vector<double> harmonics_;
};

}  // namespace matlas::zonal
