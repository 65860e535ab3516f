#include "manifold/gram_update.h"

#include <algorithm>

#include "core/blas.h"
#include "core/check.h"
#include "core/parallel.h"

namespace matlas {

GramAccumulator::GramAccumulator(Eigen::Index n, std::size_t max_columns)
    : n_(n), high_(std::max<std::size_t>(1, slices(max_columns)), Eigen::MatrixXd::Zero(n, n)), low_(high_) {}

void GramAccumulator::add_product(const double* product, std::size_t s) {
  Eigen::MatrixXd& high = high_[s];
  Eigen::MatrixXd& low = low_[s];
  for (Eigen::Index j = 0; j < n_; ++j) {
    const double* column = product + j * n_;
    double* h = high.col(j).data();
    double* l = low.col(j).data();
    for (Eigen::Index i = 0; i <= j; ++i) add_compensated(h[i], l[i], column[i]);
  }
}

void GramAccumulator::add_slice(const double* a, std::size_t ld, std::size_t columns, std::size_t s) {
  const std::size_t first = s * kSlice;
  if (first >= columns) return;
  const auto count = static_cast<int>(std::min(kSlice, columns - first));
  thread_local std::vector<double> product;
  product.resize(static_cast<std::size_t>(n_ * n_));
  // Row-major n x k with leading dimension ld is column-major k x n: P = A^T' A' = A A^T.
  blas::openblas().dsyrk(CblasColMajor, CblasUpper, CblasTrans, static_cast<int>(n_), count, 1.0, a + first,
              static_cast<int>(ld), 0.0, product.data(), static_cast<int>(n_));
  add_product(product.data(), s);
}

void GramAccumulator::add_slice(const float* a, std::size_t ld, std::size_t columns, std::size_t s) {
  const std::size_t first = s * kSlice;
  if (first >= columns) return;
  const auto count = static_cast<int>(std::min(kSlice, columns - first));
  const auto n = static_cast<int>(n_);
  thread_local std::vector<float> product;
  thread_local std::vector<double> widened;
  product.resize(static_cast<std::size_t>(n_ * n_));
  widened.resize(product.size());
  blas::openblas().ssyrk(CblasColMajor, CblasUpper, CblasTrans, n, count, 1.0f, a + first, static_cast<int>(ld),
                         0.0f, product.data(), n);
  for (Eigen::Index j = 0; j < n_; ++j)
    for (Eigen::Index i = 0; i <= j; ++i) widened[static_cast<std::size_t>(j * n_ + i)] = product[static_cast<std::size_t>(j * n_ + i)];
  add_product(widened.data(), s);
}

void GramAccumulator::total(Eigen::MatrixXd& high, Eigen::MatrixXd& low) const {
  high = Eigen::MatrixXd::Zero(n_, n_);
  low = Eigen::MatrixXd::Zero(n_, n_);
  for (std::size_t s = 0; s < high_.size(); ++s)
    for (Eigen::Index j = 0; j < n_; ++j)
      for (Eigen::Index i = 0; i <= j; ++i) {
        add_compensated(high(i, j), low(i, j), high_[s](i, j));
        low(i, j) += low_[s](i, j);
      }
  symmetrize_from_upper(high);
  symmetrize_from_upper(low);
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
  Eigen::MatrixXd high, low;
  total(high, low);
  return high + low;
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
