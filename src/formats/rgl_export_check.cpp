#include "formats/rgl_export_check.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "brdf/albedo.h"
#include "core/parallel.h"

namespace matlas {

namespace {

double fidelity_luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

}  // namespace

RglFidelity check_rgl_fidelity(const RglBsdf& file, const BrdfTable& table, const RglFidelityOptions& o) {
  RglFidelity r;
  const MerlDims& dims = table.dims();
  // Relative RMS at the bin centres, parallel over theta_h.
  std::vector<double> diff(static_cast<std::size_t>(dims.theta_h), 0.0), ref(diff.size(), 0.0);
  parallel_for_each(0, static_cast<std::size_t>(dims.theta_h), [&](std::size_t i) {
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const HalfDiffAngles a = bin_centre(dims, static_cast<int>(i), j, k);
        const DirectionPair d = from_half_diff(a);
        if (!(d.wi.z() > 0) || !(d.wo.z() > 0)) continue;
        bool all = true;
        const Rgb t = table.bin_rgb(dims.flat(static_cast<int>(i), j, k), &all);
        if (!all) continue;
        // matlas' cosine-weighted RMSE (eval/brdf_distance.h): c (f - g) per value, c = cos_i cos_o.
        const double c = d.wi.z() * d.wo.z();
        const Rgb f = file.eval(d.wi, d.wo);
        diff[i] += c * c * (f - t).square().sum();
        ref[i] += c * c * t.square().sum();
      }
  });
  double dsum = 0, rsum = 0;
  for (std::size_t i = 0; i < diff.size(); ++i) dsum += diff[i], rsum += ref[i];
  r.relative_rms = rsum > 0 ? std::sqrt(dsum / rsum) : 0.0;

  // Between the centres: one point per bin, uniform over the bin's coordinates (a fixed
  // sequence), against the table's smooth lookup where its eight bins are measured.
  std::fill(diff.begin(), diff.end(), 0.0);
  std::fill(ref.begin(), ref.end(), 0.0);
  parallel_for_each(0, static_cast<std::size_t>(dims.theta_h), [&](std::size_t i) {
    std::mt19937_64 rng(o.seed * 7919 + i);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const double xi = uniform(rng), xj = uniform(rng), xk = uniform(rng);
        HalfDiffAngles a;
        const double u = (static_cast<double>(i) + xi) / dims.theta_h;
        a.theta_h = u * u * (kPi / 2.0);
        a.theta_d = (j + xj) / dims.theta_d * (kPi / 2.0);
        a.phi_d = (k + xk) / dims.phi_d * kPi;
        const DirectionPair d = from_half_diff(a);
        if (!(d.wi.z() > 0) || !(d.wo.z() > 0)) continue;
        const TrilinearBins bins = trilinear_bins(dims, d.wi, d.wo);
        bool all = true;
        for (std::size_t b = 0; b < bins.bins.size() && all; ++b)
          if (bins.weights[b] > 0) table.bin_rgb(bins.bins[b], &all);
        if (!all) continue;
        const double c = d.wi.z() * d.wo.z();
        const Rgb t = table.lookup_smooth(d.wi, d.wo).max(0.0);
        diff[i] += c * c * (file.eval(d.wi, d.wo) - t).square().sum();
        ref[i] += c * c * t.square().sum();
      }
  });
  dsum = rsum = 0;
  for (std::size_t i = 0; i < diff.size(); ++i) dsum += diff[i], rsum += ref[i];
  r.relative_rms_between = rsum > 0 ? std::sqrt(dsum / rsum) : 0.0;

  r.angles_deg = o.angles_deg;
  const std::size_t n = o.angles_deg.size();
  r.table_albedo.assign(n, Rgb::Zero());
  r.file_albedo.assign(n, Rgb::Zero());
  r.sampled_albedo.assign(n, 0.0);
  r.variance_own.assign(n, 0.0);
  r.variance_cosine.assign(n, 0.0);
  parallel_for_each(0, n, [&](std::size_t a) {
    const Vec3 view = direction_at_theta(o.angles_deg[a] * kPi / 180.0);
    r.table_albedo[a] = half_vector_albedo([&](const Vec3& wi, const Vec3& v) { return table.lookup_smooth(wi, v); },
                                           view, o.albedo_resolution);
    // A renderer integrates eval_cosine(view, w) over w; half_vector_albedo multiplies by cos(w).
    r.file_albedo[a] =
        half_vector_albedo([&](const Vec3& w, const Vec3& v) { return file.eval(v, w); }, view, o.albedo_resolution);
    std::mt19937_64 rng(o.seed + a);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    double s1 = 0, s2 = 0, c1 = 0, c2 = 0;
    for (int k = 0; k < o.samples; ++k) {
      const double u1 = uniform(rng), u2 = uniform(rng);
      const RglBsdf::Sample s = file.sample(view, u1, u2);
      const double own = s.pdf > 0 ? fidelity_luminance(file.eval_cosine(view, s.wo)) / s.pdf : 0.0;
      s1 += own, s2 += own * own;
      const double rr = std::sqrt(uniform(rng)), phi = 2 * kPi * uniform(rng);
      const Vec3 w(rr * std::cos(phi), rr * std::sin(phi), std::sqrt(std::max(0.0, 1 - rr * rr)));
      const double cos_est = w.z() > 0 ? fidelity_luminance(file.eval_cosine(view, w)) * kPi / w.z() : 0.0;
      c1 += cos_est, c2 += cos_est * cos_est;
    }
    const double m = static_cast<double>(o.samples);
    r.sampled_albedo[a] = s1 / m;
    r.variance_own[a] = std::max(0.0, s2 / m - (s1 / m) * (s1 / m));
    r.variance_cosine[a] = std::max(0.0, c2 / m - (c1 / m) * (c1 / m));
  });
  for (std::size_t a = 0; a < n; ++a) {
    const Rgb rel = (r.file_albedo[a] - r.table_albedo[a]).abs() / r.table_albedo[a].max(0.01);
    r.albedo_error = std::max(r.albedo_error, rel.maxCoeff());
  }
  return r;
}

}  // namespace matlas
