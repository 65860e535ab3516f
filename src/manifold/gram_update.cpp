#include "manifold/gram_update.h"

#include <algorithm>
#include <vector>

#include <cblas.h>

#include "core/parallel.h"

namespace matlas {

void add_gram_upper(const BlockMatrix& a, Eigen::MatrixXd& upper) {
  const int n = static_cast<int>(a.rows()), k = static_cast<int>(a.cols());
  if (k == 0) return;
  constexpr int kChunk = 4096;  // columns per dsyrk call (n x kChunk doubles: ~3 MB for n = 100)
  const int chunks = (k + kChunk - 1) / kChunk;
  const int saved = openblas_get_num_threads();
  openblas_set_num_threads(1);
  std::vector<Eigen::MatrixXd> partial(static_cast<std::size_t>(chunks));
  parallel_for_each(0, static_cast<std::size_t>(chunks), [&](std::size_t c) {
    const int first = static_cast<int>(c) * kChunk, count = std::min(kChunk, k - first);
    Eigen::MatrixXd& s = partial[c] = Eigen::MatrixXd::Zero(n, n);
    // Row-major n x k with leading dimension k is column-major k x n: S += A^T' A' = A A^T.
    cblas_dsyrk(CblasColMajor, CblasUpper, CblasTrans, n, count, 1.0, a.data() + first, k, 1.0, s.data(), n);
  });
  for (const Eigen::MatrixXd& s : partial) upper.triangularView<Eigen::Upper>() += s;
  openblas_set_num_threads(saved);
}

void symmetrize_from_upper(Eigen::MatrixXd& s) { s.triangularView<Eigen::StrictlyLower>() = s.transpose(); }

}  // namespace matlas
