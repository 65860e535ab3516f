#include "zonal/sh.h"

#include <algorithm>
#include <cmath>

#include "brdf/types.h"

namespace matlas::zonal {

void normalized_legendre(int L, double x, std::vector<double>& out) {
  out.assign(triangle_size(L), 0.0);
  const double s = std::sqrt(std::max(0.0, 1.0 - x * x));
  double pmm = std::sqrt(1.0 / (4.0 * kPi));  // Pbar_0^0
  for (int m = 0; m <= L; ++m) {
    if (m > 0) pmm *= std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * s;
    out[lm_index(m, m)] = pmm;
    if (m == L) break;
    double p_prev = pmm;
    double p = std::sqrt(2.0 * m + 3.0) * x * pmm;  // Pbar_{m+1}^m
    out[lm_index(m + 1, m)] = p;
    for (int l = m + 2; l <= L; ++l) {
      const double ll = static_cast<double>(l), mm = static_cast<double>(m);
      const double a = std::sqrt((4.0 * ll * ll - 1.0) / (ll * ll - mm * mm));
      const double b = std::sqrt(((ll - 1.0) * (ll - 1.0) - mm * mm) / (4.0 * (ll - 1.0) * (ll - 1.0) - 1.0));
      const double next = a * (x * p - b * p_prev);
      out[lm_index(l, m)] = next;
      p_prev = p;
      p = next;
    }
  }
}

LegendreRecurrence::LegendreRecurrence(int L)
    : L_(L), diagonal_(static_cast<std::size_t>(L) + 1, 0.0), a_(triangle_size(L), 0.0), b_(triangle_size(L), 0.0) {
  for (int m = 1; m <= L; ++m) diagonal_[static_cast<std::size_t>(m)] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
  for (int m = 0; m <= L; ++m)
    for (int l = m + 2; l <= L; ++l) {
      const double ll = static_cast<double>(l), mm = static_cast<double>(m);
      a_[lm_index(l, m)] = std::sqrt((4.0 * ll * ll - 1.0) / (ll * ll - mm * mm));
      b_[lm_index(l, m)] = std::sqrt(((ll - 1.0) * (ll - 1.0) - mm * mm) / (4.0 * (ll - 1.0) * (ll - 1.0) - 1.0));
    }
}

void LegendreRecurrence::evaluate(double x, double* out) const {
  const double s = std::sqrt(std::max(0.0, 1.0 - x * x));
  double pmm = std::sqrt(1.0 / (4.0 * kPi));
  for (int m = 0; m <= L_; ++m) {
    if (m > 0) pmm *= diagonal_[static_cast<std::size_t>(m)] * s;
    out[lm_index(m, m)] = pmm;
    if (m == L_) break;
    double p_prev = pmm, p = std::sqrt(2.0 * m + 3.0) * x * pmm;
    out[lm_index(m + 1, m)] = p;
    for (int l = m + 2; l <= L_; ++l) {
      const std::size_t j = lm_index(l, m);
      const double next = a_[j] * (x * p - b_[j] * p_prev);
      out[j] = next;
      p_prev = p;
      p = next;
    }
  }
}

void zonal_harmonics(int L, double t, std::vector<double>& out) {
  out.resize(static_cast<std::size_t>(L) + 1);
  double p_prev = 1.0, p = t;  // P_0, P_1
  for (int l = 0; l <= L; ++l) {
    double pl;
    if (l == 0) {
      pl = 1.0;
    } else if (l == 1) {
      pl = t;
    } else {
      pl = ((2.0 * l - 1.0) * t * p - (l - 1.0) * p_prev) / l;
      p_prev = p;
      p = pl;
    }
    out[static_cast<std::size_t>(l)] = std::sqrt((2.0 * l + 1.0) / (4.0 * kPi)) * pl;
  }
}

}  // namespace matlas::zonal
