#include "formats/spectral_rgb.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/error.h"

namespace matlas {

namespace {

/// Piecewise-Gaussian lobe of the analytic colour-matching functions.
double lobe(double lambda, double mu, double s1, double s2) {
  const double t = (lambda - mu) / (lambda < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}

/// XYZ to linear sRGB.
constexpr double kXyzToRgb[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};

double sigmoid(double z) { return 0.5 + 0.5 * z / std::sqrt(1.0 + z * z); }
double sigmoid_slope(double z) {
  const double r = 1.0 / std::sqrt(1.0 + z * z);
  return 0.5 * r * r * r;
}

}  // namespace

std::array<double, 3> cie_xyz(double l) {
  return {1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2),
          0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1),
          1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8)};
}

std::vector<std::array<double, 3>> spectral_to_rgb_weights(const std::vector<float>& wavelengths) {
  const std::size_t n = wavelengths.size();
  std::vector<std::array<double, 3>> w(n, std::array<double, 3>{0, 0, 0});
  std::array<double, 3> white{0, 0, 0};
  const auto add = [&](std::size_t k, double weight, double nm) {
    const auto xyz = cie_xyz(nm);
    for (std::size_t c = 0; c < 3; ++c) {
      const double v = weight * (kXyzToRgb[c][0] * xyz[0] + kXyzToRgb[c][1] * xyz[1] + kXyzToRgb[c][2] * xyz[2]);
      w[k][c] += v;
      white[c] += v;
    }
  };
  if (n == 1) {
    add(0, 1.0, wavelengths[0]);
  } else {
    // The spectrum is linear between its wavelengths (as renderers interpolate it) and zero
    // outside: each sample's weight is the integral of its hat function times the colour-matching
    // functions, by the midpoint rule in steps of at most 0.5 nm over 300-900 nm (the functions
    // vanish outside; a file's wavelengths may be anything finite).
    constexpr double kFrom = 300.0, kTo = 900.0;
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const double lo = wavelengths[k], hi = wavelengths[k + 1];
      const double a = std::max(lo, kFrom), b = std::min(hi, kTo);
      if (!(b > a)) continue;
      const int steps = static_cast<int>(std::ceil((b - a) / 0.5));  // at most 1200
      const double h = (b - a) / steps;
      for (int i = 0; i < steps; ++i) {
        const double nm = a + (i + 0.5) * h, t = (nm - lo) / (hi - lo);
        add(k, (1.0 - t) * h, nm);
        add(k + 1, t * h, nm);
      }
    }
  }
  for (auto& row : w)
    for (std::size_t c = 0; c < 3; ++c) row[c] = white[c] != 0 ? row[c] / white[c] : 0.0;
  return w;
}

SpectralUpsampler::SpectralUpsampler(std::vector<float> wavelengths) : wavelengths_(std::move(wavelengths)) {
  if (wavelengths_.size() < 3) throw Error("spectral upsampling: need at least 3 wavelengths");
  for (std::size_t k = 1; k < wavelengths_.size(); ++k)
    if (!(wavelengths_[k] > wavelengths_[k - 1])) throw Error("spectral upsampling: wavelengths must increase");
  const double lo = wavelengths_.front(), span = wavelengths_.back() - lo;
  for (float l : wavelengths_) t_.push_back((l - lo) / span);
  weights_ = spectral_to_rgb_weights(wavelengths_);
}

std::array<double, 3> SpectralUpsampler::reduce(const float* s) const {
  std::array<double, 3> rgb{0, 0, 0};
  for (std::size_t k = 0; k < weights_.size(); ++k)
    for (std::size_t c = 0; c < 3; ++c) rgb[c] += weights_[k][c] * s[k];
  return rgb;
}

SpectralUpsampler::Fit SpectralUpsampler::fit(const std::array<double, 3>& rgb_in, const Fit* start) const {
  std::array<double, 3> rgb{};
  for (std::size_t c = 0; c < 3; ++c) rgb[c] = std::isfinite(rgb_in[c]) ? std::max(0.0, rgb_in[c]) : 0.0;
  Fit f;
  const double top = std::max({rgb[0], rgb[1], rgb[2]});
  if (!(top > 0)) return f;  // black: scale 0
  f.scale = 2.0 * top;
  Eigen::Vector3d target(rgb[0] / f.scale, rgb[1] / f.scale, rgb[2] / f.scale);
  // Residual and Jacobian of reduce(sigma(c0 t^2 + c1 t + c2)) - target.
  const auto evaluate = [&](const Eigen::Vector3d& c, Eigen::Vector3d& r, Eigen::Matrix3d* J) {
    r = -target;
    if (J != nullptr) J->setZero();
    for (std::size_t k = 0; k < t_.size(); ++k) {
      const double t = t_[k], z = (c[0] * t + c[1]) * t + c[2];
      const double s = sigmoid(z), ds = sigmoid_slope(z);
      for (int ch = 0; ch < 3; ++ch) {
        const double w = weights_[k][static_cast<std::size_t>(ch)];
        r[ch] += w * s;
        if (J != nullptr) {
          (*J)(ch, 0) += w * ds * t * t;
          (*J)(ch, 1) += w * ds * t;
          (*J)(ch, 2) += w * ds;
        }
      }
    }
  };
  // Levenberg-Marquardt from c; returns the cost reached.
  const auto solve = [&](Eigen::Vector3d& c) {
    Eigen::Vector3d r;
    Eigen::Matrix3d J;
    evaluate(c, r, &J);
    double cost = r.squaredNorm(), mu = 1e-3;
    for (int it = 0; it < 100 && cost > 1e-16; ++it) {
      const Eigen::Matrix3d A = J.transpose() * J;
      const Eigen::Vector3d g = J.transpose() * r;
      Eigen::Matrix3d D = A;
      D.diagonal() += mu * (A.diagonal().array() + 1e-12).matrix();
      const Eigen::Vector3d step = D.ldlt().solve(-g);
      const Eigen::Vector3d trial = c + step;
      Eigen::Vector3d rt;
      evaluate(trial, rt, nullptr);
      if (rt.allFinite() && rt.squaredNorm() < cost) {
        c = trial;
        evaluate(c, r, &J);
        cost = r.squaredNorm();
        mu = std::max(1e-9, mu * 0.3);
      } else {
        mu *= 10.0;
        if (mu > 1e12) break;
      }
    }
    return cost;
  };
  // Start: the grey of the same mean (a constant spectrum reduces to it), or the neighbour's fit;
  // from a neighbour whose colour is far (a saturated sample beside a grey one: its sigmoid flat,
  // the Jacobian near 0) the steps can stall, and then the fit starts again from grey.
  const double g = std::clamp(target.mean(), 1e-6, 1.0 - 1e-6);
  const Eigen::Vector3d grey(0, 0, (g - 0.5) / std::sqrt(g * (1.0 - g)));  // sigma^-1(g)
  Eigen::Vector3d c = start != nullptr && start->scale > 0
                          ? Eigen::Vector3d(start->coefficients[0], start->coefficients[1], start->coefficients[2])
                          : grey;
  double cost = solve(c);
  if (start != nullptr && start->scale > 0 && cost > 1e-12) {
    Eigen::Vector3d again = grey;
    const double cost_again = solve(again);
    if (cost_again < cost) c = again, cost = cost_again;
  }
  f.coefficients = {c[0], c[1], c[2]};
  f.error = std::sqrt(cost) * f.scale / top;
  return f;
}

void SpectralUpsampler::spectrum(const Fit& f, float* out) const {
  for (std::size_t k = 0; k < t_.size(); ++k) {
    const double t = t_[k];
    const double z = (f.coefficients[0] * t + f.coefficients[1]) * t + f.coefficients[2];
    out[k] = static_cast<float>(f.scale * sigmoid(z));
  }
}

}  // namespace matlas
