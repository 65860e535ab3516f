#include "manifold/dense_product.h"

#include <cblas.h>

#include "core/error.h"

namespace matlas {

Eigen::MatrixXd blas_product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.cols() != b.rows()) throw Error("blas_product: inner dimensions differ (internal error)");
  Eigen::MatrixXd c(a.rows(), b.cols());
  if (c.size() == 0) return c;
  if (a.cols() == 0) return c.setZero();
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(a.rows()), static_cast<int>(b.cols()),
              static_cast<int>(a.cols()), 1.0, a.data(), static_cast<int>(a.rows()), b.data(),
              static_cast<int>(b.rows()), 0.0, c.data(), static_cast<int>(c.rows()));
  return c;
}

}  // namespace matlas
