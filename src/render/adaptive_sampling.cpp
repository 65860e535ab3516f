#include "render/adaptive_sampling.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"

namespace matlas::render {

void AdaptiveSampling::validate() const {
  if (!(floor > 0 && floor <= 1)) throw Error("adaptive sampling: floor must be in (0, 1], got " + std::to_string(floor));
  if (!(cap >= 1 && cap <= 4096)) throw Error("adaptive sampling: cap must be in [1, 4096], got " + std::to_string(cap));
  if (radius < 0 || radius > 8) throw Error("adaptive sampling: radius must be in [0, 8], got " + std::to_string(radius));
  if (min_trial_spp < 2) throw Error("adaptive sampling: min_trial_spp must be at least 2, got " + std::to_string(min_trial_spp));
}

int pixel_sample_count(int spp, double share) { return std::max(1, static_cast<int>(std::lround(spp * share))); }

void check_pixel_samples(const std::vector<double>* shares, int width, int height) {
  if (!shares) return;
  if (shares->size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw Error("pixel_samples has " + std::to_string(shares->size()) + " shares for a " + std::to_string(width) + "x" +
                std::to_string(height) + " image");
  for (const double share : *shares)
    if (!(share > 0) || !std::isfinite(share) || share > 1e6)
      throw Error("pixel_samples: every share must be positive and finite, got " + std::to_string(share));
}

namespace {

/// The mean of the shares clamp(sigma / lambda, floor, cap).
double mean_share(const std::vector<double>& sigma, double lambda, const AdaptiveSampling& s) {
  double sum = 0;
  for (const double v : sigma) sum += std::clamp(v / lambda, s.floor, s.cap);
  return sum / static_cast<double>(sigma.size());
}

}  // namespace

std::vector<double> linear_and_shown_weights(const Image& image, const std::vector<bool>& measured, const ToneMap& tone) {
  MATLAS_CHECK_EQ(measured.size(), image.pixel_count());
  const float scale = static_cast<float>(std::exp2(tone.exposure));
  const auto shown = [&](double v) {
    return static_cast<double>(srgb_encode(std::min(1.0f, tone_curve(static_cast<float>(v), scale, tone.curve))));
  };
  double linear = 0, displayed = 0;
  for (std::size_t p = 0; p < measured.size(); ++p)
    if (measured[p])
      for (std::size_t c = 0; c < 3; ++c) {
        const double v = image.rgb[3 * p + c];
        linear += v * v;
        displayed += shown(v) * shown(v);
      }
  std::vector<double> weights(image.rgb.size(), 0.0);
  if (!(linear > 0) || !(displayed > 0)) return std::vector<double>(image.rgb.size(), 1.0);
  for (std::size_t i = 0; i < weights.size(); ++i) {
    const double v = std::max(0.0, static_cast<double>(image.rgb[i]));
    const double h = std::max(1e-4, 0.02 * v);  // the displayed value's slope, central differences
    const double slope = (shown(v + h) - shown(std::max(0.0, v - h))) / (v + h - std::max(0.0, v - h));
    weights[i] = 1.0 / linear + slope * slope / displayed;
  }
  return weights;
}

std::vector<double> adaptive_pixel_samples(const Image& a, const Image& b, const std::vector<int>& samples,
                                           const AdaptiveSampling& settings, const std::vector<double>& weights) {
  settings.validate();
  MATLAS_CHECK(a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size(), "two estimates of one image");
  const std::size_t w = static_cast<std::size_t>(a.width), h = static_cast<std::size_t>(a.height), pixels = w * h;
  MATLAS_CHECK_EQ(samples.size(), pixels);
  MATLAS_CHECK(weights.empty() || weights.size() == a.rgb.size(), "a weight per pixel and channel");
  // One sample's variance per pixel: n (a - b)^2 / 4 over the channels.
  std::vector<double> variance(pixels, 0.0);
  double largest = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    double d2 = 0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a.rgb[3 * p + c]) - static_cast<double>(b.rgb[3 * p + c]);
      d2 += (weights.empty() ? 1.0 : weights[3 * p + c]) * d * d;
    }
    variance[p] = std::isfinite(d2) ? 0.25 * samples[p] * d2 : 0.0;
    largest = std::max(largest, variance[p]);
  }
  if (!(largest > 0)) return std::vector<double>(pixels, 1.0);
  // Averaged over the window around each pixel (clipped at the image's border): a box filter,
  // rows then columns.
  const int r = settings.radius;
  std::vector<double> rows(pixels), sigma(pixels);
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      double sum = 0;
      int count = 0;
      for (int dx = -r; dx <= r; ++dx) {
        const long xx = static_cast<long>(x) + dx;
        if (xx < 0 || xx >= static_cast<long>(w)) continue;
        sum += variance[y * w + static_cast<std::size_t>(xx)];
        ++count;
      }
      rows[y * w + x] = sum / count;
    }
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      double sum = 0;
      int count = 0;
      for (int dy = -r; dy <= r; ++dy) {
        const long yy = static_cast<long>(y) + dy;
        if (yy < 0 || yy >= static_cast<long>(h)) continue;
        sum += rows[static_cast<std::size_t>(yy) * w + x];
        ++count;
      }
      sigma[y * w + x] = std::sqrt(sum / count);
    }
  // lambda with mean share 1: the mean falls as lambda grows (bisection on log lambda). When even
  // the cap everywhere there is noise leaves the mean under 1 (noise in a few pixels only), the
  // shares at that limit are scaled up to mean 1.
  double lo = std::sqrt(largest) / settings.cap * 1e-3, hi = std::sqrt(largest) / settings.floor * 1e3;
  std::vector<double> shares(pixels);
  if (mean_share(sigma, lo, settings) < 1) {
    const double mean = mean_share(sigma, lo, settings);
    for (std::size_t p = 0; p < pixels; ++p) shares[p] = std::clamp(sigma[p] / lo, settings.floor, settings.cap) / mean;
    return shares;
  }
  for (int it = 0; it < 100; ++it) {
    const double mid = std::sqrt(lo * hi);
    (mean_share(sigma, mid, settings) > 1 ? lo : hi) = mid;
  }
  const double lambda = std::sqrt(lo * hi);
  double mean = 0;
  for (std::size_t p = 0; p < pixels; ++p) mean += shares[p] = std::clamp(sigma[p] / lambda, settings.floor, settings.cap);
  mean /= static_cast<double>(pixels);
  for (double& s : shares) s /= mean;  // exactly 1 (the bisection leaves a rounding)
  return shares;
}

}  // namespace matlas::render
