#include "manifold/gram_update.h"

#include <algorithm>

#include "core/blas.h"
#include "core/check.h"
#include "core/parallel.h"

namespace matlas {

GramAccumulator::GramAccumulator(Eigen::Index n, std::size_t max_columns)
    : n_(n), high_(Eigen::MatrixXd::Zero(n, n)), low_(Eigen::MatrixXd::Zero(n, n)),
      product_(std::max<std::size_t>(1, slices(max_columns))), product_single_(product_.size()) {}

template <class T>
void GramAccumulator::add_product(const T* product) {
  std::lock_guard lock(mutex_);
  for (Eigen::Index j = 0; j < n_; ++j) {
    const T* column = product + j * n_;
    double* h = high_.col(j).data();
    double* l = low_.col(j).data();
    for (Eigen::Index i = 0; i <= j; ++i) add_compensated(h[i], l[i], static_cast<double>(column[i]));
  }
}

void GramAccumulator::add_slice(const double* a, std::size_t ld, std::size_t columns, std::size_t s) {
  const std::size_t first = s * kSlice;
  if (first >= columns) return;
  const auto count = static_cast<int>(std::min(kSlice, columns - first));
  HugePageVector<double>& product = product_[s];
  product.resize(static_cast<std::size_t>(n_ * n_));
  // Row-major n x k with leading dimension ld is column-major k x n: P = A^T' A' = A A^T.
  blas::openblas().dsyrk(CblasColMajor, CblasUpper, CblasTrans, static_cast<int>(n_), count, 1.0, a + first,
              static_cast<int>(ld), 0.0, product.data(), static_cast<int>(n_));
  add_product(product.data());
}

void GramAccumulator::add_slice(const float* a, std::size_t ld, std::size_t columns, std::size_t s) {
  const std::size_t first = s * kSlice;
  if (first >= columns) return;
  const auto count = static_cast<int>(std::min(kSlice, columns - first));
  const auto n = static_cast<int>(n_);
  HugePageVector<float>& product = product_single_[s];
  product.resize(static_cast<std::size_t>(n_ * n_));
  blas::openblas().ssyrk(CblasColMajor, CblasUpper, CblasTrans, n, count, 1.0f, a + first, static_cast<int>(ld),
                         0.0f, product.data(), n);
  add_product(product.data());  // a float is exact in double
}

void GramAccumulator::total(Eigen::MatrixXd& value, Eigen::MatrixXd& rest) const {
  value = high_;
  rest = low_;
  symmetrize_from_upper(value);
  symmetrize_from_upper(rest);
  round_compensated(value, rest);
}

void round_compensated(Eigen::MatrixXd& value, Eigen::MatrixXd& low) {
  MATLAS_CHECK_EQ(value.size(), low.size());
  for (Eigen::Index k = 0; k < value.size(); ++k) {
    const double high = value.data()[k], rest = low.data()[k];
    double sum = 0, error = 0;
    add_compensated(sum, error, high);
    add_compensated(sum, error, rest);
    value.data()[k] = sum;
    low.data()[k] = error;
  }
}

Eigen::MatrixXd GramAccumulator::total() const {
  Eigen::MatrixXd value, rest;
  total(value, rest);
  return value;
}

void add_gram_upper(const BlockMatrix& a, Eigen::MatrixXd& upper) {
  if (a.cols() == 0) return;
  const auto k = static_cast<std::size_t>(a.cols());
  GramAccumulator gram(a.rows(), k);
  parallel_for_each(0, GramAccumulator::slices(k), [&](std::size_t s) { gram.add_slice(a, s); });
  upper.triangularView<Eigen::Upper>() += gram.total();
}

void symmetrize_from_upper(Eigen::MatrixXd& s) { s.triangularView<Eigen::StrictlyLower>() = s.transpose(); }

}  // namespace matlas
