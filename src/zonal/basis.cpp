#include "zonal/basis.h"

#include <cmath>
#include <string>

#include <Eigen/SVD>

#include "core/check.h"
#include "core/error.h"
#include "zonal/sh.h"

namespace matlas::zonal {

ZonalBasis::ZonalBasis(int L) : L_(L) {
  if (L < 0 || L > 128) throw Error("zonal bands must be between 0 and 128, got " + std::to_string(L));
  std::vector<double> p;
  for (int l = 0; l <= L; ++l) {
    Eigen::MatrixXd a(l + 1, l + 1);
    for (int k = 0; k <= l; ++k) {
      const double alpha = kPi * k / (l + 1);
      alpha_.push_back(alpha);
      band_.push_back(l);
      normalized_legendre(l, std::cos(alpha), p);  // d has phi = 0: cos(m phi) = 1
      for (int m = 0; m <= l; ++m)
        a(m, k) = std::sqrt(4.0 * kPi / (2.0 * l + 1.0)) * (m > 0 ? std::sqrt(2.0) : 1.0) * p[lm_index(l, m)];
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a);
    const auto& s = svd.singularValues();
    condition_.push_back(s(0) / s(s.size() - 1));
    inverse_.push_back(a.inverse());
  }
}

Vec3 ZonalBasis::direction(std::size_t j) const {
  MATLAS_DCHECK_LT(j, alpha_.size());
  return {std::sin(alpha_[j]), 0.0, std::cos(alpha_[j])};
}

}  // namespace matlas::zonal
