#include "manifold/dense_product.h"

#include <algorithm>
#include <vector>

#include "core/blas.h"
#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"

namespace matlas {

namespace {

/// Columns of a's inner dimension per partial product when the inner dimension is split.
constexpr Eigen::Index kInnerChunk = 1 << 16;

/// c = a * b (or c += when beta is 1) for column-major blocks given by pointer and leading dimension.
void gemm(Eigen::Index m, Eigen::Index p, Eigen::Index k, const double* a, Eigen::Index lda, const double* b,
          Eigen::Index ldb, double beta, double* c, Eigen::Index ldc) {
  blas::openblas().dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(m), static_cast<int>(p),
                         static_cast<int>(k), 1.0, a, static_cast<int>(lda), b, static_cast<int>(ldb), beta, c,
                         static_cast<int>(ldc));
}

}  // namespace

Eigen::MatrixXd blas_product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  MATLAS_CHECK_EQ(a.cols(), b.rows());
  const Eigen::Index m = a.rows(), k = a.cols(), p = b.cols();
  Eigen::MatrixXd c(m, p);
  if (c.size() == 0) return c;
  if (k == 0) return c.setZero();
  // OpenBLAS runs single-threaded (core/blas.h): the workers take parts of the product. A long
  // inner dimension with a small result (a Gram matrix T^T T) is cut into fixed chunks whose
  // partial products are added in chunk order, so the result does not depend on the thread count.
  if (k > 4 * std::max(m, p) && k > kInnerChunk) {
    const auto chunks = static_cast<std::size_t>((k + kInnerChunk - 1) / kInnerChunk);
    std::vector<Eigen::MatrixXd> partial(chunks);
    parallel_for_each(0, chunks, [&](std::size_t s) {
      const Eigen::Index first = static_cast<Eigen::Index>(s) * kInnerChunk, count = std::min(kInnerChunk, k - first);
      partial[s].resize(m, p);
      gemm(m, p, count, a.data() + first * m, m, b.data() + first, k, 0.0, partial[s].data(), m);
    });
    c = partial[0];
    for (std::size_t s = 1; s < chunks; ++s) c += partial[s];
    return c;
  }
  // Otherwise the larger side of the result is cut into bands, one dgemm each.
  const Eigen::Index band = 64;
  if (p >= m) {
    parallel_for(0, static_cast<std::size_t>(p), [&](std::size_t lo, std::size_t hi) {
      const auto j = static_cast<Eigen::Index>(lo);
      gemm(m, static_cast<Eigen::Index>(hi - lo), k, a.data(), m, b.data() + j * k, k, 0.0, c.data() + j * m, m);
    }, band);
  } else {
    parallel_for(0, static_cast<std::size_t>(m), [&](std::size_t lo, std::size_t hi) {
      const auto i = static_cast<Eigen::Index>(lo);
      gemm(static_cast<Eigen::Index>(hi - lo), p, k, a.data() + i, m, b.data(), k, 0.0, c.data() + i, m);
    }, band);
  }
  return c;
}

}  // namespace matlas
