#include "zonal/prefilter.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "zonal/lobes.h"
#include "zonal/sh.h"

namespace matlas::zonal {

namespace {

void angles(const Vec3& d, double* theta, double* phi) {
  *theta = std::acos(std::clamp(d.y(), -1.0, 1.0));
  double p = std::atan2(d.z(), d.x());
  if (p < 0) p += 2.0 * kPi;
  *phi = p;
}

/// cos(m phi_c) and sin(m phi_c) for phi_c = 2 pi (c + offset) / columns, m <= L.
class Trig {
public:
  Trig(int L, int columns, double offset) : stride_(static_cast<std::size_t>(L) + 1) {
    cos_.resize(stride_ * static_cast<std::size_t>(columns));
    sin_.resize(cos_.size());
    for (int c = 0; c < columns; ++c)
      for (int m = 0; m <= L; ++m) {
        const double a = m * 2.0 * kPi * (c + offset) / columns;
        cos_[static_cast<std::size_t>(c) * stride_ + static_cast<std::size_t>(m)] = std::cos(a);
        sin_[static_cast<std::size_t>(c) * stride_ + static_cast<std::size_t>(m)] = std::sin(a);
      }
  }
  double cos(int c, int m) const { return cos_[static_cast<std::size_t>(c) * stride_ + static_cast<std::size_t>(m)]; }
  double sin(int c, int m) const { return sin_[static_cast<std::size_t>(c) * stride_ + static_cast<std::size_t>(m)]; }

private:
  std::size_t stride_;
  std::vector<double> cos_, sin_;
};

/// sqrt(2)^(m>0) for the real harmonics.
double real_factor(int m) { return m > 0 ? std::sqrt(2.0) : 1.0; }

/// Bilinear read of a lat-long map of h rows (poles as rows) and w = 2 (h - 1) periodic columns.
Rgb bilinear(const std::vector<float>& map, int h, const Vec3& d) {
  double theta, phi;
  angles(d, &theta, &phi);
  const int w = 2 * (h - 1);
  const double fx = phi / (2.0 * kPi) * w;
  const double fy = std::clamp(theta / kPi * (h - 1), 0.0, h - 1.0);
  const int x0 = static_cast<int>(std::floor(fx)), y0 = std::min(static_cast<int>(fy), h - 2);
  const double tx = fx - x0, ty = fy - y0;
  Rgb sum = Rgb::Zero();
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const int x = ((x0 + dx) % w + w) % w;
      const float* p = &map[(static_cast<std::size_t>(y0 + dy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 3];
      sum += (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * Rgb(p[0], p[1], p[2]);
    }
  return sum;
}

/// The real SH coefficients of a radiance map up to band L (cosine and sine parts).
struct Coefficients {
  std::vector<Rgb> cos, sin;
};

/// Projects the environment on the SH up to band L by quadrature over a lat-long grid (the map's
/// rows and columns times `supersample`, or `constant_grid` rows for a constant environment).
/// The grid's cells tile the map's texels exactly, whatever the map's rotation (its columns are
/// turned with the map): each texel, constant, is integrated by the same s x s points, not by
/// whichever points of a fixed grid fall into it (which, for a small bright light, was off by
/// up to 2 % in band 2 at s = 8).
Coefficients project_environment(const render::Environment& env, int L, const PrefilterSettings& settings) {
  const bool constant = env.height() <= 0;  // a constant environment has no map
  const int rows = constant ? settings.constant_grid : env.height() * settings.supersample;
  const int cols = constant ? 2 * rows : env.width() * settings.supersample;
  const std::size_t n = triangle_size(L);
  // Per row: Fourier sums over phi, then the Legendre functions of the row (rows run in parallel
  // into per-row partial sums, added in order: deterministic).
  std::vector<std::vector<Rgb>> row_cos(static_cast<std::size_t>(rows)), row_sin(static_cast<std::size_t>(rows));
  const double dtheta = kPi / rows, dphi = 2.0 * kPi / cols;
  // Column c at phi = 2 pi (c + offset) / cols: the map's u = (c + 0.5) / cols (Environment's
  // phi = 2 pi (u - 0.5) + rotation).
  const double offset = constant ? 0.5 : 0.5 + cols * (env.rotation() / (2.0 * kPi) - 0.5);
  const Trig columns(L, cols, offset);
  parallel_for_each(0, static_cast<std::size_t>(rows), [&](std::size_t r) {
    const double theta = (static_cast<double>(r) + 0.5) * dtheta;
    std::vector<Rgb> fc(static_cast<std::size_t>(L) + 1, Rgb::Zero()), fs(static_cast<std::size_t>(L) + 1, Rgb::Zero());
    for (int c = 0; c < cols; ++c) {
      const double phi = (c + offset) * dphi;
      const Rgb radiance = env.eval(Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
      for (int m = 0; m <= L; ++m) {
        fc[static_cast<std::size_t>(m)] += radiance * columns.cos(c, m);
        fs[static_cast<std::size_t>(m)] += radiance * columns.sin(c, m);
      }
    }
    std::vector<double> p;
    normalized_legendre(L, std::cos(theta), p);
    // The row's exact solid angle (the midpoint rule's sin(theta) dtheta is off by O(dtheta^2)).
    const double w = (std::cos(theta - dtheta / 2) - std::cos(theta + dtheta / 2)) * dphi;
    row_cos[r].assign(n, Rgb::Zero());
    row_sin[r].assign(n, Rgb::Zero());
    for (int l = 0; l <= L; ++l)
      for (int m = 0; m <= l; ++m) {
        const double y = real_factor(m) * p[lm_index(l, m)] * w;
        row_cos[r][lm_index(l, m)] = y * fc[static_cast<std::size_t>(m)];
        row_sin[r][lm_index(l, m)] = y * fs[static_cast<std::size_t>(m)];
      }
  });
  Coefficients sh;
  sh.cos.assign(n, Rgb::Zero());
  sh.sin.assign(n, Rgb::Zero());
  for (int r = 0; r < rows; ++r)
    for (std::size_t i = 0; i < n; ++i) {
      sh.cos[i] += row_cos[static_cast<std::size_t>(r)][i];
      sh.sin[i] += row_sin[static_cast<std::size_t>(r)][i];
    }
  return sh;
}

/// Band l of the radiance on a lat-long grid of max(8, ceil(texels_per_band (l + 1))) rows
/// (poles as rows) and 2 (rows - 1) columns, RGB float; `rows` receives the row count.
std::vector<float> tabulate_band(int l, double texels_per_band, const Coefficients& sh, int* rows) {
  const int h = std::max(8, static_cast<int>(std::ceil(texels_per_band * (l + 1)))), w = 2 * (h - 1);
  std::vector<float> map(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  std::vector<double> p;
  const double scale = std::sqrt(4.0 * kPi / (2.0 * l + 1.0));
  const Trig trig(l, w, 0.0);
  for (int y = 0; y < h; ++y) {
    normalized_legendre(l, std::cos(y * kPi / (h - 1)), p);
    for (int x = 0; x < w; ++x) {
      Rgb e = Rgb::Zero();
      for (int m = 0; m <= l; ++m) {
        const double pl = real_factor(m) * p[lm_index(l, m)];
        e += pl * (sh.cos[lm_index(l, m)] * trig.cos(x, m) + sh.sin[lm_index(l, m)] * trig.sin(x, m));
      }
      float* out = &map[(static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 3];
      for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(scale * e[c]);
    }
  }
  *rows = h;
  return map;
}

/// The radiance convolved with a lobe of sharpness kappa (zonal coefficients k_l, truncated
/// where k_l < e^-9) on a lat-long grid of h rows: per row, A_m = sum_l k_l sqrt(2)^(m>0)
/// Pbar_l^m L_l^m (and B_m for sin), then per column sum_m A_m cos(m phi) + B_m sin(m phi).
std::vector<float> lobe_map(double kappa, int L, int h, const Coefficients& sh) {
  const int w = 2 * (h - 1);
  const std::vector<double> k = lobe_legendre(kappa, L);
  int top = 0;  // the lobe's highest band: k_l >= e^-9
  while (top < L && k[static_cast<std::size_t>(top) + 1] >= std::exp(-9.0)) ++top;
  const Trig trig(top, w, 0.0);
  std::vector<float> map(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  parallel_for_each(0, static_cast<std::size_t>(h), [&](std::size_t row) {
    std::vector<double> p;
    normalized_legendre(top, std::cos(static_cast<double>(row) * kPi / (h - 1)), p);
    std::vector<Rgb> a(static_cast<std::size_t>(top) + 1, Rgb::Zero()), b(a);
    for (int l = 0; l <= top; ++l)
      for (int m = 0; m <= l; ++m) {
        const double y = k[static_cast<std::size_t>(l)] * real_factor(m) * p[lm_index(l, m)];
        a[static_cast<std::size_t>(m)] += y * sh.cos[lm_index(l, m)];
        b[static_cast<std::size_t>(m)] += y * sh.sin[lm_index(l, m)];
      }
    for (int x = 0; x < w; ++x) {
      Rgb e = Rgb::Zero();
      for (int m = 0; m <= top; ++m) e += a[static_cast<std::size_t>(m)] * trig.cos(x, m) + b[static_cast<std::size_t>(m)] * trig.sin(x, m);
      float* out = &map[(row * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 3];
      for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(e[c]);
    }
  });
  return map;
}

}  // namespace

PrefilteredEnvironment::PrefilteredEnvironment(const render::Environment& env, const PrefilterSettings& settings)
    : settings_(settings) {
  const int bands = settings.bands;
  if (bands < 0 || bands > 128) throw Error("prefilter bands must be between 0 and 128, got " + std::to_string(bands));
  validate_lobes(settings.lobes);
  if (!settings.lobes.empty() && (settings.lobe_bands < 1 || settings.lobe_bands > 512 || settings.lobe_rows < 8 ||
                                  settings.lobe_rows > 4097))
    throw Error("prefilter lobe resolution out of range");
  // The SH of the environment up to L: the bands' and, with lobes, the lobes' highest band.
  const int L = settings.lobes.empty() ? bands : std::max(bands, settings.lobe_bands);
  if (!(settings.texels_per_band > 0) || settings.texels_per_band > 64 || settings.supersample < 1 ||
      settings.supersample > 16 || settings.constant_grid < 4)
    throw Error("prefilter resolution out of range");
  Coefficients sh = project_environment(env, L, settings);
  heights_.resize(static_cast<std::size_t>(bands) + 1);
  maps_.resize(static_cast<std::size_t>(bands) + 1);
  parallel_for_each(0, static_cast<std::size_t>(bands) + 1, [&](std::size_t band) {
    maps_[band] = tabulate_band(static_cast<int>(band), settings.texels_per_band, sh, &heights_[band]);
  });
  for (double kappa : settings.lobes) {
    const double share = settings.scale_lobe_rows ? std::sqrt(kappa / settings.lobes.back()) : 1.0;
    lobe_heights_.push_back(std::max(std::min(65, settings.lobe_rows),
                                     1 + static_cast<int>(std::lround((settings.lobe_rows - 1) * share))));
    lobe_maps_.push_back(lobe_map(kappa, L, lobe_heights_.back(), sh));
  }
  cos_coeffs_ = std::move(sh.cos);
  sin_coeffs_ = std::move(sh.sin);
}

Rgb PrefilteredEnvironment::lobe_lookup(std::size_t i, const Vec3& d) const {
  MATLAS_DCHECK_LT(i, lobe_maps_.size());
  return bilinear(lobe_maps_[i], lobe_heights_[i], d);
}

Rgb PrefilteredEnvironment::coefficient(int l, int m) const {
  MATLAS_CHECK(l >= 0 && m >= -l && m <= l && lm_index(l, std::abs(m)) < cos_coeffs_.size(), "a coefficient (l, m)");
  return m >= 0 ? cos_coeffs_[lm_index(l, m)] : sin_coeffs_[lm_index(l, -m)];
}

Rgb PrefilteredEnvironment::exact(int l, const Vec3& d) const {
  double theta, phi;
  angles(d, &theta, &phi);
  std::vector<double> p;
  normalized_legendre(l, std::cos(theta), p);
  Rgb e = Rgb::Zero();
  for (int m = 0; m <= l; ++m)
    e += real_factor(m) * p[lm_index(l, m)] *
         (cos_coeffs_[lm_index(l, m)] * std::cos(m * phi) + sin_coeffs_[lm_index(l, m)] * std::sin(m * phi));
  return std::sqrt(4.0 * kPi / (2.0 * l + 1.0)) * e;
}

Rgb PrefilteredEnvironment::lookup(int l, const Vec3& d) const {
  MATLAS_DCHECK(l >= 0 && static_cast<std::size_t>(l) < maps_.size(), "a band of the environment");
  return bilinear(maps_[static_cast<std::size_t>(l)], heights_[static_cast<std::size_t>(l)], d);
}

}  // namespace matlas::zonal
