#include "artist/fit_error.h"

#include <algorithm>
#include <cmath>

#include "brdf/albedo.h"
#include "brdf/merl_grid.h"
#include "core/parallel.h"

namespace matlas::artist {

FitError fit_error(const BrdfTable& table, const BrdfFunction& model, const FitErrorOptions& o) {
  FitError r;
  const MerlDims& dims = table.dims();
  const auto n_h = static_cast<std::size_t>(dims.theta_h);
  std::vector<double> diff(n_h, 0.0), ref(n_h, 0.0), cbrt_sq(n_h, 0.0), values(n_h, 0.0);
  parallel_for_each(0, n_h, [&](std::size_t i) {
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const DirectionPair d = from_half_diff(bin_centre(dims, static_cast<int>(i), j, k));
        if (!(d.wi.z() > 0) || !(d.wo.z() > 0)) continue;
        bool all = true;
        const Rgb t = table.bin_rgb(dims.flat(static_cast<int>(i), j, k), &all);
        if (!all) continue;
        const double c = d.wi.z() * d.wo.z();
        const Rgb f = model(d.wi, d.wo);
        diff[i] += c * c * (f - t).square().sum();
        ref[i] += c * c * t.square().sum();
        for (int ch = 0; ch < 3; ++ch) {
          const double e = std::cbrt(c * f[ch]) - std::cbrt(c * t[ch]);
          cbrt_sq[i] += e * e;
        }
        values[i] += 3;
      }
  });
  double dsum = 0, rsum = 0, csum = 0, count = 0;
  for (std::size_t i = 0; i < n_h; ++i) dsum += diff[i], rsum += ref[i], csum += cbrt_sq[i], count += values[i];
  r.relative_rms = rsum > 0 ? std::sqrt(dsum / rsum) : 0.0;
  r.cbrt_distance = count > 0 ? std::sqrt(csum / count) : 0.0;

  r.angles_deg = o.angles_deg;
  const std::size_t n = o.angles_deg.size();
  r.table_albedo.assign(n, Rgb::Zero());
  r.fit_albedo.assign(n, Rgb::Zero());
  parallel_for_each(0, n, [&](std::size_t a) {
    const Vec3 view = direction_at_theta(o.angles_deg[a] * kPi / 180.0);
    r.table_albedo[a] = half_vector_albedo([&](const Vec3& wi, const Vec3& v) { return table.lookup_smooth(wi, v); },
                                           view, o.albedo_resolution);
    r.fit_albedo[a] = half_vector_albedo(model, view, o.albedo_resolution);
  });
  for (std::size_t a = 0; a < n; ++a)
    for (int c = 0; c < 3; ++c)
      r.albedo_error = std::max(r.albedo_error, std::abs(r.fit_albedo[a][c] - r.table_albedo[a][c]) /
                                                    std::max(r.table_albedo[a][c], 0.01));
  return r;
}

}  // namespace matlas::artist
