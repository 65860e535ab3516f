#include "brdf/ndf_extraction.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/error.h"

namespace matlas {

namespace {

/// Midpoints in u per node interval of the sigma integral.
constexpr int kNdfSigmaSubPoints = 8;

/// integral over phi in [0, 2 pi) of max(0, a + b cos phi), b >= 0.
double ndf_clamped_cosine_azimuth_integral(double a, double b) {
  if (a >= b) return 2.0 * kPi * a;
  if (a <= -b) return 0.0;
  const double phi0 = std::acos(std::clamp(-a / b, -1.0, 1.0));
  return 2.0 * (a * phi0 + b * std::sin(phi0));
}

/// Luminance of the back-scattering per theta_h bin: theta_d bins under 3 deg, every phi_d,
/// measured values only; -1 where a bin has none.
std::vector<double> ndf_backscattering_per_bin(const BrdfTable& table) {
  const MerlDims& dims = table.dims();
  const int theta_d_bins = std::max(1, static_cast<int>(std::lround(3.0 / 90.0 * dims.theta_d)));
  std::vector<double> out(static_cast<std::size_t>(dims.theta_h), -1.0);
  constexpr double kLum[3] = {0.2126, 0.7152, 0.0722};
  for (int i = 0; i < dims.theta_h; ++i) {
    double sum = 0;
    int count = 0;
    for (int j = 0; j < theta_d_bins; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const std::size_t bin = dims.flat(i, j, k);
        bool all = true;
        const Rgb v = table.bin_rgb(bin, &all);
        if (!all) continue;
        sum += kLum[0] * v[0] + kLum[1] * v[1] + kLum[2] * v[2];
        ++count;
      }
    if (count > 0) out[static_cast<std::size_t>(i)] = std::max(sum / count, 0.0);
  }
  return out;
}

}  // namespace

MicrofacetNdf::MicrofacetNdf(std::vector<double> node_values) : d_(std::move(node_values)) {
  MATLAS_CHECK_GE(d_.size(), std::size_t{2});
  double peak = 0;
  for (double v : d_) {
    MATLAS_CHECK(std::isfinite(v) && v >= 0, "D must be finite and non-negative: " + std::to_string(v));
    peak = std::max(peak, v);
  }
  MATLAS_CHECK_GT(peak, 0.0);
  const double norm = normalisation();
  MATLAS_CHECK_GT(norm, 0.0);
  for (double& v : d_) v /= norm;
}

double MicrofacetNdf::at_unit(double u) const {
  const double x = std::clamp(u, 0.0, 1.0) * static_cast<double>(d_.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(x), d_.size() - 2);
  const double t = x - static_cast<double>(i);
  return (1 - t) * d_[i] + t * d_[i + 1];
}

double MicrofacetNdf::operator()(double theta) const { return at_unit(std::sqrt(std::max(theta, 0.0) * 2.0 / kPi)); }

double MicrofacetNdf::projected_area(double theta_i) const {
  const double ci = std::cos(theta_i), si = std::sin(theta_i);
  const std::size_t intervals = d_.size() - 1;
  const int points = static_cast<int>(intervals) * kNdfSigmaSubPoints;
  const double du = 1.0 / points;
  double sum = 0;
  for (int p = 0; p < points; ++p) {
    const double u = (p + 0.5) * du, theta = 0.5 * kPi * u * u;
    const double st = std::sin(theta), ct = std::cos(theta);
    // dm = sin(theta) dtheta dphi, dtheta = pi u du
    sum += at_unit(u) * ndf_clamped_cosine_azimuth_integral(ci * ct, si * st) * st * kPi * u * du;
  }
  return sum;
}

MicrofacetNdf ndf_from_backscattering(const std::vector<double>& backscattering, const NdfExtractionOptions& options,
                                      NdfExtractionReport* report) {
  MATLAS_CHECK_GE(backscattering.size(), std::size_t{2});
  MATLAS_CHECK_GE(options.iterations, 1);
  const std::size_t n = backscattering.size();
  double peak = 0;
  for (double v : backscattering) {
    MATLAS_CHECK(std::isfinite(v) && v >= 0, "D must be finite and non-negative: " + std::to_string(v));
    peak = std::max(peak, v);
  }
  std::vector<double> f(n);
  for (std::size_t k = 0; k < n; ++k) f[k] = peak > 0 ? std::max(backscattering[k], options.floor * peak) : 1.0;
  std::vector<double> cosines(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double u = static_cast<double>(k) / static_cast<double>(n - 1);
    cosines[k] = std::cos(0.5 * kPi * u * u);
  }
  // D_0 = f cos (sigma_0 = 1); a D that vanishes at grazing (cos = 0) is kept positive by the
  // floor relative to the peak.
  auto floored = [&](std::vector<double> d) {
    double top = 0;
    for (double v : d) top = std::max(top, v);
    for (double& v : d) v = std::max(v, options.floor * top);
    return MicrofacetNdf(std::move(d));
  };
  std::vector<double> d0(n);
  for (std::size_t k = 0; k < n; ++k) d0[k] = f[k] * cosines[k];
  MicrofacetNdf ndf = floored(std::move(d0));
  NdfExtractionReport r;
  for (int it = 0; it < options.iterations; ++it) {
    std::vector<double> next(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double u = static_cast<double>(k) / static_cast<double>(n - 1);
      next[k] = f[k] * cosines[k] * ndf.projected_area(0.5 * kPi * u * u);
    }
    MicrofacetNdf updated = floored(std::move(next));
    double change = 0;
    for (std::size_t k = 0; k < n; ++k)
      change = std::max(change, std::fabs(updated.nodes()[k] - ndf.nodes()[k]) / std::max(ndf.nodes()[k], 1e-300));
    ndf = std::move(updated);
    r.iterations = it + 1;
    r.last_change = change;
  }
  if (report) *report = r;
  return ndf;
}

MicrofacetNdf extract_ndf(const BrdfTable& table, const NdfExtractionOptions& options, NdfExtractionReport* report) {
  MATLAS_CHECK_GE(options.nodes, 2);
  std::vector<double> per_bin = ndf_backscattering_per_bin(table);
  const std::size_t bins = per_bin.size();
  // Missing bins: nearest measured neighbour (in u); none measured: no information, uniform.
  std::vector<double> filled(bins, -1.0);
  for (std::size_t i = 0; i < bins; ++i) {
    if (per_bin[i] >= 0) {
      filled[i] = per_bin[i];
      continue;
    }
    for (std::size_t d = 1; d < bins && filled[i] < 0; ++d) {
      if (i >= d && per_bin[i - d] >= 0) filled[i] = per_bin[i - d];
      else if (i + d < bins && per_bin[i + d] >= 0) filled[i] = per_bin[i + d];
    }
    if (filled[i] < 0) filled[i] = 0;
  }
  // Nodes: linear in u between bin centres (u = (i + 0.5) / bins), constant beyond the ends.
  const auto n = static_cast<std::size_t>(options.nodes);
  std::vector<double> f(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double x = static_cast<double>(k) / static_cast<double>(n - 1) * static_cast<double>(bins) - 0.5;
    if (x <= 0) f[k] = filled.front();
    else if (x >= static_cast<double>(bins - 1)) f[k] = filled.back();
    else {
      const auto i = static_cast<std::size_t>(x);
      const double t = x - static_cast<double>(i);
      f[k] = (1 - t) * filled[i] + t * filled[i + 1];
    }
  }
  return ndf_from_backscattering(f, options, report);
}

}  // namespace matlas
