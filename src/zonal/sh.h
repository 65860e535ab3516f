#pragma once
// Real spherical harmonics and zonal kernels, orthonormal over the unit sphere.
//
//   Y_l^m(theta, phi) = sqrt(2) Pbar_l^m(cos theta) cos(m phi)   (m > 0)
//   Y_l^0(theta)      =         Pbar_l^0(cos theta)               = sqrt((2l+1)/4pi) P_l(cos theta)
//   Y_l^-m            = sqrt(2) Pbar_l^m(cos theta) sin(m phi)
// with Pbar_l^m the associated Legendre functions normalised so that
// 2 pi * integral_{-1}^{1} Pbar_l^m(x)^2 dx = 1 (no Condon-Shortley phase). Pbar is computed by the
// standard three-term recurrences in m then l, stable to far higher degrees than used here.
#include <cstddef>
#include <vector>

namespace matlas::zonal {

/// Index of (l, m), 0 <= m <= l, in a triangular table: l (l + 1) / 2 + m.
inline std::size_t lm_index(int l, int m) {
  return static_cast<std::size_t>(l) * static_cast<std::size_t>(l + 1) / 2 + static_cast<std::size_t>(m);
}
/// Size of a triangular table up to degree L: (L + 1)(L + 2) / 2.
inline std::size_t triangle_size(int L) { return lm_index(L + 1, 0); }

/// Pbar_l^m(x) for 0 <= m <= l <= L into out[lm_index(l, m)] (resized to triangle_size(L)).
void normalized_legendre(int L, double x, std::vector<double>& out);

/// normalized_legendre with its recurrence factors computed once: for many evaluations at one L
/// (the renderer's control variate evaluates it at every sample). Same values to rounding.
class LegendreRecurrence {
public:
  explicit LegendreRecurrence(int L);
  int degree() const { return L_; }
  /// Pbar_l^m(x) into out[lm_index(l, m)], out holding triangle_size(L) values.
  void evaluate(double x, double* out) const;

private:
  int L_;
  std::vector<double> diagonal_;  ///< per m > 0: sqrt((2m + 1) / (2m))
  std::vector<double> a_, b_;     ///< per (l, m), l >= m + 2: the three-term factors
};

/// The zonal harmonic of band l as a function of the cosine t to its axis:
/// Y_l^0(t) = sqrt((2l+1)/4pi) P_l(t), for every l <= L into out[l] (resized to L + 1).
void zonal_harmonics(int L, double t, std::vector<double>& out);

}  // namespace matlas::zonal
