#include "formats/rgl_warp.h"

#include <algorithm>
#include <cmath>

namespace matlas {

std::pair<std::size_t, double> param_interval(std::span<const float> values, double x) {
  if (values.size() < 2) return {0, 0.0};
  const auto first_not_below =
      static_cast<std::size_t>(std::lower_bound(values.begin(), values.end(), x,
                                                [](float v, double t) { return static_cast<double>(v) < t; }) -
                               values.begin());
  const std::size_t i = std::min(first_not_below == 0 ? 0 : first_not_below - 1, values.size() - 2);
  const double p0 = values[i], p1 = values[i + 1];
  const double w = p1 > p0 ? std::clamp((x - p0) / (p1 - p0), 0.0, 1.0) : 0.0;
  return {i, w};
}

ParamBlend blend_params(std::span<const float> outer, double outer_x, std::span<const float> inner, double inner_x) {
  const auto [oi, ow] = param_interval(outer, outer_x);
  const auto [ii, iw] = param_interval(inner, inner_x);
  const std::size_t n_inner = std::max<std::size_t>(inner.size(), 1);
  ParamBlend b;
  b.count = 0;
  const int outer_steps = outer.size() > 1 ? 2 : 1, inner_steps = inner.size() > 1 ? 2 : 1;
  for (int a = 0; a < outer_steps; ++a) {
    for (int c = 0; c < inner_steps; ++c) {
      const double wa = outer_steps == 1 ? 1.0 : (a ? ow : 1.0 - ow);
      const double wc = inner_steps == 1 ? 1.0 : (c ? iw : 1.0 - iw);
      b.slice[static_cast<std::size_t>(b.count)] = (oi + static_cast<std::size_t>(a)) * n_inner + ii + static_cast<std::size_t>(c);
      b.weight[static_cast<std::size_t>(b.count)] = wa * wc;
      ++b.count;
    }
  }
  return b;
}

RglWarp2D::RglWarp2D(std::vector<float>&& data, std::size_t nx, std::size_t ny, std::size_t slices)
    : nx_(nx), ny_(ny), slices_(slices), raw_(std::move(data)) {}

RglWarp2D::RglWarp2D(std::span<const float> data, std::size_t nx, std::size_t ny, std::size_t slices, bool build_cdf)
    : nx_(nx), ny_(ny), slices_(slices) {
  if (!build_cdf) {
    raw_.assign(data.begin(), data.end());
    return;
  }
  data_.assign(data.begin(), data.end());
  const std::size_t size = nx * ny;
  conditional_.assign(data_.size(), 0.0);
  marginal_.assign(slices * ny, 0.0);
  integral_.assign(slices, 0.0);
  for (std::size_t s = 0; s < slices; ++s) {
    double* d = data_.data() + s * size;
    double* cond = conditional_.data() + s * size;
    double* marg = marginal_.data() + s * ny;
    // Row integrals of the piecewise-linear rows (trapezoids, patch width 1), then the integral
    // of the row totals over y (linear between rows).
    for (std::size_t y = 0; y < ny; ++y) {
      double sum = 0;
      cond[y * nx] = 0;
      for (std::size_t x = 0; x + 1 < nx; ++x) {
        sum += 0.5 * (d[y * nx + x] + d[y * nx + x + 1]);
        cond[y * nx + x + 1] = sum;
      }
    }
    double sum = 0;
    marg[0] = 0;
    for (std::size_t y = 0; y + 1 < ny; ++y) {
      sum += 0.5 * (cond[y * nx + nx - 1] + cond[(y + 1) * nx + nx - 1]);
      marg[y + 1] = sum;
    }
    integral_[s] = sum;
    const double scale = sum > 0 ? 1.0 / sum : 0.0;
    for (std::size_t i = 0; i < size; ++i) {
      d[i] *= scale;
      cond[i] *= scale;
    }
    for (std::size_t y = 0; y < ny; ++y) marg[y] *= scale;
  }
}

RglWarp2D::Cell RglWarp2D::cell(double x, double y) const {
  const double fx = std::clamp(x, 0.0, 1.0) * static_cast<double>(nx_ - 1);
  const double fy = std::clamp(y, 0.0, 1.0) * static_cast<double>(ny_ - 1);
  Cell c;
  c.px = std::min(static_cast<std::size_t>(fx), nx_ - 2);
  c.py = std::min(static_cast<std::size_t>(fy), ny_ - 2);
  c.s = fx - static_cast<double>(c.px), c.t = fy - static_cast<double>(c.py);
  return c;
}

RglWarp2D::Patch RglWarp2D::patch(double x, double y, const ParamBlend& b) const {
  const Cell c = cell(x, y);
  Patch p;
  p.px = c.px, p.py = c.py, p.s = c.s, p.t = c.t;
  const std::size_t i = p.py * nx_ + p.px;
  p.index = i;
  p.v00 = value(i, b), p.v10 = value(i + 1, b);
  p.v01 = value(i + nx_, b), p.v11 = value(i + nx_ + 1, b);
  return p;
}

double RglWarp2D::eval(double x, double y, const ParamBlend& b) const {
  const auto [px, py, i, s, t, v00, v10, v01, v11] = patch(x, y, b);
  const double value = (1 - t) * ((1 - s) * v00 + s * v10) + t * ((1 - s) * v01 + s * v11);
  return integral_.empty() ? value : value * static_cast<double>((nx_ - 1) * (ny_ - 1));
}

std::array<double, 2> RglWarp2D::invert(double x, double y, const ParamBlend& b) const {
  const auto [px, py, i, s, t, v00, v10, v01, v11] = patch(x, y, b);
  const std::size_t size = nx_ * ny_;
  // The density along the row at height t is linear between c0 and c1 inside the patch.
  const double c0 = (1 - t) * v00 + t * v01, c1 = (1 - t) * v10 + t * v11;
  const double inside = s * (c0 + 0.5 * s * (c1 - c0));
  const double before = (1 - t) * at(conditional_, size, i, b) + t * at(conditional_, size, i + nx_, b);
  const double r0 = at(conditional_, size, py * nx_ + nx_ - 1, b);
  const double r1 = at(conditional_, size, (py + 1) * nx_ + nx_ - 1, b);
  const double row_total = (1 - t) * r0 + t * r1;
  const double u = row_total > 0 ? (before + inside) / row_total : std::clamp(x, 0.0, 1.0);
  const double v = at(marginal_, ny_, py, b) + t * (r0 + 0.5 * t * (r1 - r0));
  return {std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)};
}

namespace {

/// The s in [0,1] with s * (a + 0.5 * s * (b - a)) = r: the inverse of the integral of a linear
/// density going from a to b over the unit interval (stable form of the quadratic's root).
double solve_linear_cdf(double a, double b, double r) {
  if (r <= 0) return 0.0;
  const double disc = a * a + 2.0 * (b - a) * r;
  const double denom = a + std::sqrt(std::max(disc, 0.0));
  const double s = denom > 0 ? 2.0 * r / denom : 0.0;
  return std::clamp(s, 0.0, 1.0);
}

}  // namespace

std::array<double, 2> RglWarp2D::sample(double u, double v, const ParamBlend& b) const {
  const std::size_t size = nx_ * ny_;
  u = std::clamp(u, 0.0, 1.0);
  v = std::clamp(v, 0.0, 1.0);
  // Row: last row start whose marginal CDF is below v.
  std::size_t lo = 0, hi = ny_ - 2;
  while (lo < hi) {
    const std::size_t mid = (lo + hi + 1) / 2;
    if (at(marginal_, ny_, mid, b) <= v) lo = mid;
    else hi = mid - 1;
  }
  const std::size_t py = lo;
  const double r0 = at(conditional_, size, py * nx_ + nx_ - 1, b);
  const double r1 = at(conditional_, size, (py + 1) * nx_ + nx_ - 1, b);
  const double t = solve_linear_cdf(r0, r1, v - at(marginal_, ny_, py, b));
  // Column, in the row at height t.
  const double target = u * ((1 - t) * r0 + t * r1);
  auto cdf = [&](std::size_t x) {
    return (1 - t) * at(conditional_, size, py * nx_ + x, b) + t * at(conditional_, size, (py + 1) * nx_ + x, b);
  };
  lo = 0;
  hi = nx_ - 2;
  while (lo < hi) {
    const std::size_t mid = (lo + hi + 1) / 2;
    if (cdf(mid) <= target) lo = mid;
    else hi = mid - 1;
  }
  const std::size_t px = lo, i = py * nx_ + px;
  const double c0 = (1 - t) * value(i, b) + t * value(i + nx_, b);
  const double c1 = (1 - t) * value(i + 1, b) + t * value(i + nx_ + 1, b);
  const double s = solve_linear_cdf(c0, c1, target - cdf(px));
  return {(static_cast<double>(px) + s) / static_cast<double>(nx_ - 1),
          (static_cast<double>(py) + t) / static_cast<double>(ny_ - 1)};
}

}  // namespace matlas
