#pragma once
// The rotated-zonal-harmonic basis of a cosine-weighted BRDF slice.
//
// Local frame of a slice: normal +z, view direction wo = (sin theta_o, 0, cos theta_o). For an
// isotropic BRDF the slice rho(wi) = f(wi, wo) max(cos theta_i, 0) is even in y, so its band-l
// part lies in the (l+1)-dimensional span of the real harmonics Y_l^m, m = 0..l (cos m phi).
// Band l is represented by l+1 zonal kernels Y_l^0(d . wi) around the directions
//
//     d_{l,k} = (sin alpha_{l,k}, 0, cos alpha_{l,k}),  alpha_{l,k} = k pi / (l+1),  k = 0..l,
//
// equally spaced on the half circle of the plane of incidence (k = 0 is the normal). By the
// addition theorem, Y_l^0(d . w) = sqrt(4pi/(2l+1)) sum_m Y_l^m(d) Y_l^m(w), and a kernel around
// a direction of that plane has no sin(m phi) part, so the l+1 kernels span exactly the even band
// l subspace. The change of basis a_l = A_l lambda_l, A_l[m][k] = sqrt(4pi/(2l+1)) Y_l^m(d_{l,k}),
// has condition number 1.0, 1.39, 1.62, 1.90, 2.25 for l = 1, 4, 8, 16, 32 (docs/REALTIME.md):
// the fit is well conditioned at every band used.
//
// Coefficients are indexed j = lm_index(l, k) (zonal/sh.h): band after band, K = (L+1)(L+2)/2.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "brdf/types.h"

namespace matlas::zonal {

class ZonalBasis {
public:
  /// Bands 0..L; throws matlas::Error for L outside [0, 128].
  explicit ZonalBasis(int L);

  int bands() const { return L_; }
  std::size_t size() const { return alpha_.size(); }  ///< K
  /// alpha_{l,k} of coefficient j (radians, from the normal towards wo).
  double alpha(std::size_t j) const { return alpha_[j]; }
  int band(std::size_t j) const { return band_[j]; }
  /// d_{l,k} in the local frame.
  Vec3 direction(std::size_t j) const;
  /// lambda_l = A_l^{-1} a_l: a_l holds the even SH coefficients of band l (m = 0..l).
  const Eigen::MatrixXd& inverse(int l) const { return inverse_[static_cast<std::size_t>(l)]; }
  /// Condition number (2-norm) of A_l.
  double condition(int l) const { return condition_[static_cast<std::size_t>(l)]; }

private:
  int L_;
  std::vector<double> alpha_;
  std::vector<int> band_;
  std::vector<Eigen::MatrixXd> inverse_;
  std::vector<double> condition_;
};

}  // namespace matlas::zonal
