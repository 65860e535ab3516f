#include "manifold/gram_update.h"

#include <algorithm>

#include "core/blas.h"
#include "core/parallel.h"

namespace matlas {

GramAccumulator::GramAccumulator(Eigen::Index n, std::size_t max_columns)
    : n_(n), upper_(std::max<std::size_t>(1, slices(max_columns)), Eigen::MatrixXd::Zero(n, n)) {}

void GramAccumulator::add_slice(const double* a, std::size_t ld, std::size_t columns, std::size_t s) {
  const std::size_t first = s * kSlice;
  if (first >= columns) return;
  const auto count = static_cast<int>(std::min(kSlice, columns - first));
  // Row-major n x k with leading dimension ld is column-major k x n: S += A^T' A' = A A^T.
  blas::openblas().dsyrk(CblasColMajor, CblasUpper, CblasTrans, static_cast<int>(n_), count, 1.0, a + first,
              static_cast<int>(ld), 1.0, upper_[s].data(), static_cast<int>(n_));
}

void GramAccumulator::add_slice(const float* a, std::size_t ld, std::size_t columns, std::size_t s) {
  const std::size_t first = s * kSlice;
  if (first >= columns) return;
  const auto count = static_cast<int>(std::min(kSlice, columns - first));
  const auto n = static_cast<int>(n_);
  thread_local std::vector<float> product;
  product.resize(static_cast<std::size_t>(n_ * n_));
  blas::openblas().ssyrk(CblasColMajor, CblasUpper, CblasTrans, n, count, 1.0f, a + first, static_cast<int>(ld),
                         0.0f, product.data(), n);
  Eigen::MatrixXd& upper = upper_[s];
  for (Eigen::Index j = 0; j < n_; ++j) {
    const float* column = product.data() + j * n_;
    double* sum = upper.col(j).data();
    for (Eigen::Index i = 0; i <= j; ++i) sum[i] += column[i];
  }
}

Eigen::MatrixXd GramAccumulator::total() const {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n_, n_);
  for (const Eigen::MatrixXd& u : upper_) s.triangularView<Eigen::Upper>() += u;
  symmetrize_from_upper(s);
  return s;
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
