#include "render/denoise.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"

namespace matlas::render {

void DenoiseSettings::validate() const {
  if (search_radius < 0 || search_radius > 32)
    throw Error("denoise: the search radius must be in 0..32, got " + std::to_string(search_radius));
  if (patch_radius < 0 || patch_radius > 32)
    throw Error("denoise: the patch radius must be in 0..32, got " + std::to_string(patch_radius));
  if (!(strength > 0) || !std::isfinite(strength))
    throw Error("denoise: the strength must be positive and finite, got " + std::to_string(strength));
}

namespace {

constexpr int kBandRows = 16;

struct Plane {
  int width = 0, height = 0;
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
};

/// Per pixel, the variance of A - B averaged over the channels and over the pixels of the same
/// region in its 3 x 3 neighbourhood (a single (A - B)^2 is a one-sample estimate).
std::vector<float> difference_variance(const Plane& plane, const Image& a, const Image& b,
                                       const std::vector<std::uint8_t>& region) {
  const std::size_t n = plane.index(0, plane.height);
  std::vector<float> raw(n);
  for (std::size_t p = 0; p < n; ++p) {
    float s = 0;
    for (std::size_t c = 0; c < 3; ++c) {
      const float d = a.rgb[3 * p + c] - b.rgb[3 * p + c];
      s += d * d;
    }
    raw[p] = s / 3;
  }
  std::vector<float> out(n);
  for (int y = 0; y < plane.height; ++y)
    for (int x = 0; x < plane.width; ++x) {
      const std::size_t p = plane.index(x, y);
      double sum = 0;
      int count = 0;
      for (int j = std::max(0, y - 1); j <= std::min(plane.height - 1, y + 1); ++j)
        for (int i = std::max(0, x - 1); i <= std::min(plane.width - 1, x + 1); ++i) {
          const std::size_t q = plane.index(i, j);
          if (region[q] != region[p]) continue;
          sum += raw[q];
          ++count;
        }
      MATLAS_DCHECK(count > 0, "a pixel is in its own region");
      out[p] = static_cast<float>(sum / count);
    }
  return out;
}

/// Filters `values` with the non-local means weights computed on `guide` (whose per-pixel
/// variance is `variance`), rows [y0, y1) into `out`.
void cross_filter_band(const Plane& plane, const std::vector<float>& values, const std::vector<float>& guide,
                       const std::vector<float>& variance, const std::vector<std::uint8_t>& region,
                       const DenoiseSettings& s, double eps, int y0, int y1, std::vector<float>& out) {
  const int w = plane.width, h = plane.height, f = s.patch_radius, r = s.search_radius;
  const int ya = std::max(0, y0 - f), yb = std::min(h, y1 + f);  // the band with its patch halo
  const std::size_t halo = static_cast<std::size_t>(yb - ya) * w, band = static_cast<std::size_t>(y1 - y0) * w;
  const float k2 = static_cast<float>(s.strength * s.strength), fe = static_cast<float>(eps);
  std::vector<float> term(halo), valid(halo), row_term(halo), row_valid(halo);
  std::vector<double> num(band * 3, 0.0), den(band, 0.0);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      // The per-pixel term of the patch distance between p and p + (dx, dy).
      for (int y = ya; y < yb; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t t = static_cast<std::size_t>(y - ya) * w + x;
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qx >= w || qy < 0 || qy >= h) {
            term[t] = 0;
            valid[t] = 0;
            continue;
          }
          const std::size_t p = plane.index(x, y), q = plane.index(qx, qy);
          const float vp = variance[p], vq = variance[q];
          float d2 = 0;
          for (std::size_t c = 0; c < 3; ++c) {
            const float d = guide[3 * p + c] - guide[3 * q + c];
            d2 += d * d;
          }
          term[t] = (d2 / 3 - (vp + std::min(vp, vq))) / (fe + k2 * (vp + vq));
          valid[t] = 1;
        }
      // Box sums over the patch: along the rows, then the columns.
      for (int y = ya; y < yb; ++y) {
        const std::size_t base = static_cast<std::size_t>(y - ya) * w;
        for (int x = 0; x < w; ++x) {
          float st = 0, sv = 0;
          for (int i = std::max(0, x - f); i <= std::min(w - 1, x + f); ++i) {
            st += term[base + i];
            sv += valid[base + i];
          }
          row_term[base + x] = st;
          row_valid[base + x] = sv;
        }
      }
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qx >= w || qy < 0 || qy >= h) continue;
          const std::size_t p = plane.index(x, y), q = plane.index(qx, qy);
          if (region[p] == 0 || region[p] != region[q]) continue;
          float st = 0, sv = 0;
          for (int j = std::max(ya, y - f); j <= std::min(yb - 1, y + f); ++j) {
            st += row_term[static_cast<std::size_t>(j - ya) * w + x];
            sv += row_valid[static_cast<std::size_t>(j - ya) * w + x];
          }
          const double weight = std::exp(-std::max(0.0, static_cast<double>(st / sv)));
          const std::size_t o = static_cast<std::size_t>(y - y0) * w + x;
          for (std::size_t c = 0; c < 3; ++c) num[3 * o + c] += weight * values[3 * q + c];
          den[o] += weight;
        }
    }
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = plane.index(x, y), o = static_cast<std::size_t>(y - y0) * w + x;
      for (std::size_t c = 0; c < 3; ++c)
        out[3 * p + c] = region[p] == 0 || den[o] <= 0 ? values[3 * p + c] : static_cast<float>(num[3 * o + c] / den[o]);
    }
}

std::vector<float> cross_filter(const Plane& plane, const std::vector<float>& values, const std::vector<float>& guide,
                                const std::vector<float>& variance, const std::vector<std::uint8_t>& region,
                                const DenoiseSettings& s, double eps) {
  std::vector<float> out(values.size());
  const std::size_t bands = static_cast<std::size_t>((plane.height + kBandRows - 1) / kBandRows);
  parallel_for_each(0, bands, [&](std::size_t band) {
    const int y0 = static_cast<int>(band) * kBandRows, y1 = std::min(plane.height, y0 + kBandRows);
    cross_filter_band(plane, values, guide, variance, region, s, eps, y0, y1, out);
  });
  return out;
}

}  // namespace

DenoiseResult denoise_halves(const Image& a, const Image& b, double samples_a, double samples_b,
                             const std::vector<std::uint8_t>& region_in, const std::vector<bool>& measured,
                             const DenoiseSettings& settings) {
  settings.validate();
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw Error("denoise: the two halves differ in size (" + std::to_string(a.width) + "x" + std::to_string(a.height) +
                " and " + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
  if (!(samples_a > 0) || !(samples_b > 0) || !std::isfinite(samples_a) || !std::isfinite(samples_b))
    throw Error("denoise: the halves' sample counts must be positive");
  const std::size_t n = a.pixel_count();
  if (!region_in.empty() && region_in.size() != n)
    throw Error("denoise: the region has " + std::to_string(region_in.size()) + " labels for " + std::to_string(n) + " pixels");
  if (!measured.empty() && measured.size() != n)
    throw Error("denoise: the measured mask has " + std::to_string(measured.size()) + " entries for " +
                std::to_string(n) + " pixels");
  const std::vector<std::uint8_t> region = region_in.empty() ? std::vector<std::uint8_t>(n, 1) : region_in;
  const Plane plane{a.width, a.height};
  const double total = samples_a + samples_b;
  const std::vector<float> var_ab = difference_variance(plane, a, b, region);
  std::vector<float> var_a(n), var_b(n);
  for (std::size_t p = 0; p < n; ++p) {
    var_a[p] = static_cast<float>(var_ab[p] * samples_b / total);
    var_b[p] = static_cast<float>(var_ab[p] * samples_a / total);
  }
  // eps keeps the distance finite where the variance is 0 (a noise-free input, a black region):
  // far below any squared difference that matters, so identical patches alone are averaged there.
  double mean_square = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) mean_square += 0.5 * (double(a.rgb[i]) * a.rgb[i] + double(b.rgb[i]) * b.rgb[i]);
  const double eps = 1e-12 * (mean_square / std::max<std::size_t>(1, a.rgb.size())) + 1e-30;
  const std::vector<float> fa = cross_filter(plane, a.rgb, b.rgb, var_b, region, settings, eps);
  const std::vector<float> fb = cross_filter(plane, b.rgb, a.rgb, var_a, region, settings, eps);
  MATLAS_CHECK(fa.size() == a.rgb.size() && fb.size() == b.rgb.size(), "filtered halves of the input's size");

  DenoiseResult result;
  result.image = Image(a.width, a.height);
  double squares = 0, signal = 0;
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t i = 3 * p + c;
      const double mean = (samples_a * fa[i] + samples_b * fb[i]) / total;
      result.image.rgb[i] = static_cast<float>(mean);
      if (!measured.empty() && !measured[p]) continue;
      const double d = double(fa[i]) - fb[i];
      squares += d * d;
      signal += mean * mean;
    }
  const double variance = squares * samples_a * samples_b / (total * total);
  result.relative_error = signal > 0 ? std::sqrt(variance / signal) : 0.0;
  return result;
}

}  // namespace matlas::render
