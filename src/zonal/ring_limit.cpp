#include "zonal/ring_limit.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "core/error.h"
#include "zonal/lobes.h"
#include "zonal/sh.h"
#include "zonal/window.h"

namespace matlas::zonal {

void RingLimit::validate() const {
  if (!(floor >= 0.0 && floor <= 1.0)) throw Error("ring limit: floor must be in [0, 1], got " + std::to_string(floor));
  if (theta_rows < 4 || theta_rows > 4096 || theta_rows % 2 != 0 || phi_columns < 4 || phi_columns > 4096)
    throw Error("ring limit: the grid must have an even number of rows, 4 to 4096, and 4 to 4096 columns");
}

RingLimiter::RingLimiter(const ZonalBasis& basis, const ZonalCoefficients& layout, const RingLimit& limit)
    : limit_(limit), bands_(layout.bands), theta_o_count_(layout.theta_o_count), lobes_(layout.lobes) {
  limit.validate();
  if (basis.bands() < layout.bands)
    throw Error("ring limit: the basis has " + std::to_string(basis.bands()) + " bands, the coefficients " +
                std::to_string(layout.bands));
  const std::size_t K = layout.zonal_size(), M = lobes_.size();
  const auto P = static_cast<Eigen::Index>(limit.theta_rows) * limit.phi_columns;
  // The grid (midpoints in theta and phi; the first theta_rows / 2 rows are the upper hemisphere).
  std::vector<Vec3> w(static_cast<std::size_t>(P));
  for (int i = 0; i < limit.theta_rows; ++i)
    for (int k = 0; k < limit.phi_columns; ++k) {
      const double theta = (i + 0.5) * kPi / limit.theta_rows, phi = (k + 0.5) * kPi / limit.phi_columns;
      w[static_cast<std::size_t>(i * limit.phi_columns + k)] =
          Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  kernels_.resize(P, static_cast<Eigen::Index>(K));
  std::vector<double> zh;
  for (std::size_t j = 0; j < K; ++j) {
    const int l = basis.band(j);
    const Vec3 d = basis.direction(j);
    for (Eigen::Index p = 0; p < P; ++p) {
      zonal_harmonics(l, d.dot(w[static_cast<std::size_t>(p)]), zh);
      kernels_(p, static_cast<Eigen::Index>(j)) = zh[static_cast<std::size_t>(l)];
    }
  }
  const std::vector<double> hann = band_window(BandWindow::hann, bands_);
  factor_.resize(K);
  for (std::size_t j = 0; j < K; ++j) factor_[j] = 1.0 - hann[static_cast<std::size_t>(basis.band(j))];
  for (int t = 0; t < theta_o_count_; ++t) {
    const double theta_o = ZonalCoefficients::theta_o(t, theta_o_count_);
    const Vec3 r(-std::sin(theta_o), 0.0, std::cos(theta_o));
    Eigen::MatrixXd values(P, static_cast<Eigen::Index>(M));
    for (std::size_t i = 0; i < M; ++i) {
      const double mass = lobe_cosine_mass(lobes_[i], r.z());
      for (Eigen::Index p = 0; p < P; ++p) {
        const Vec3& wp = w[static_cast<std::size_t>(p)];
        values(p, static_cast<Eigen::Index>(i)) = lobe_value(lobes_[i], r.dot(wp)) * std::max(wp.z(), 0.0) / mass;
      }
    }
    lobe_values_.push_back(std::move(values));
  }
  area_.resize(static_cast<std::size_t>(limit.theta_rows / 2) * static_cast<std::size_t>(limit.phi_columns));
  for (std::size_t p = 0; p < area_.size(); ++p) area_[p] = std::sqrt(std::max(0.0, 1.0 - w[p].z() * w[p].z()));
}

std::vector<double> RingLimiter::apply(ZonalCoefficients& c) const {
  if (c.bands != bands_ || c.theta_o_count != theta_o_count_ || c.lobes != lobes_)
    throw Error("ring limit: coefficients of another layout than the limiter's");
  const std::size_t K = c.zonal_size(), S = c.size(), M = c.lobes.size();
  const auto T = static_cast<Eigen::Index>(theta_o_count_);
  const auto upper = static_cast<Eigen::Index>(area_.size());
  double total_area = 0.0;
  for (double a : area_) total_area += a;
  // Every sample's expansion at once: columns 3 t + channel, plain and Hann-weighted.
  Eigen::MatrixXd lambda(static_cast<Eigen::Index>(K), 3 * T), damped(static_cast<Eigen::Index>(K), 3 * T);
  for (Eigen::Index t = 0; t < T; ++t)
    for (std::size_t j = 0; j < K; ++j)
      for (int ch = 0; ch < 3; ++ch) {
        const double x = c.values[(static_cast<std::size_t>(t) * S + j) * 3 + static_cast<std::size_t>(ch)];
        lambda(static_cast<Eigen::Index>(j), 3 * t + ch) = x;
        damped(static_cast<Eigen::Index>(j), 3 * t + ch) = factor_[j] * x;
      }
  const Eigen::MatrixXd expansion = kernels_ * lambda, changes = kernels_ * damped;
  std::vector<std::pair<double, double>> level(area_.size());
  std::vector<double> ts(static_cast<std::size_t>(T), 0.0);
  Eigen::MatrixXd lobe(static_cast<Eigen::Index>(M), 3);
  for (Eigen::Index t = 0; t < T; ++t) {
    double* v = &c.values[static_cast<std::size_t>(t) * S * 3];
    // rec(s) = plain - s change: the expansion with band l weighted by w_l(s), plus the lobes.
    Eigen::MatrixXd plain = expansion.middleCols(3 * t, 3);
    if (M > 0) {
      for (std::size_t i = 0; i < M; ++i)
        for (int ch = 0; ch < 3; ++ch) lobe(static_cast<Eigen::Index>(i), ch) = v[(K + i) * 3 + static_cast<std::size_t>(ch)];
      plain += lobe_values_[static_cast<std::size_t>(t)] * lobe;
    }
    const auto change = changes.middleCols(3 * t, 3);
    // The level: the area-weighted median over the upper hemisphere of rec(1), mean over channels.
    for (Eigen::Index p = 0; p < upper; ++p)
      level[static_cast<std::size_t>(p)] = {(plain.row(p) - change.row(p)).mean(), area_[static_cast<std::size_t>(p)]};
    std::sort(level.begin(), level.end());
    double median = 0.0, below = 0.0;
    for (const auto& [value, weight] : level) {
      below += weight;
      median = value;
      if (below >= 0.5 * total_area) break;
    }
    const double lowest = -limit_.floor * std::max(median, 0.0);
    const auto minimum = [&](double s) { return (plain - s * change).minCoeff(); };
    double s = 0.0;
    if (minimum(0.0) < lowest) {
      // minimum() is concave in s: find its highest point on [0, 1] (golden section), then the least
      // s with minimum(s) >= lowest left of it (bisection: one crossing). Where no s reaches the
      // floor (a dip the window cannot lift), Hann.
      const double g = 0.5 * (std::sqrt(5.0) - 1.0);
      double lo = 0.0, hi = 1.0, a = hi - g * (hi - lo), b = lo + g * (hi - lo);
      double fa = minimum(a), fb = minimum(b);
      for (int it = 0; it < 32; ++it) {
        if (fa < fb) {
          lo = a;
          a = b;
          fa = fb;
          b = lo + g * (hi - lo);
          fb = minimum(b);
        } else {
          hi = b;
          b = a;
          fb = fa;
          a = hi - g * (hi - lo);
          fa = minimum(a);
        }
      }
      const double best = 0.5 * (lo + hi);
      if (minimum(best) < lowest) s = 1.0;
      else {
        lo = 0.0;
        hi = best;  // minimum(lo) < lowest <= minimum(hi)
        for (int it = 0; it < 24; ++it) {
          const double mid = 0.5 * (lo + hi);
          (minimum(mid) < lowest ? lo : hi) = mid;
        }
        s = hi;
      }
    }
    ts[static_cast<std::size_t>(t)] = s;
    for (std::size_t j = 0; j < K; ++j)
      for (int ch = 0; ch < 3; ++ch) v[j * 3 + static_cast<std::size_t>(ch)] *= 1.0 - s * factor_[j];
  }
  return ts;
}

}  // namespace matlas::zonal
