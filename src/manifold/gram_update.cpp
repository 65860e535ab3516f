#include "manifold/gram_update.h"

#include <vector>

#include <cblas.h>

#include "core/parallel.h"

namespace matlas {

void add_gram_upper(const BlockMatrix& a, Eigen::MatrixXd& upper) {
  const int n = static_cast<int>(a.rows()), k = static_cast<int>(a.cols());
  if (k == 0) return;
  const int saved = openblas_get_num_threads();
  openblas_set_num_threads(1);
  const std::size_t workers = std::min<std::size_t>(worker_count(), static_cast<std::size_t>(k) / 1024 + 1);
  std::vector<Eigen::MatrixXd> partial(workers);
  parallel_for(0, workers, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t w = lo; w < hi; ++w) {
      const int first = static_cast<int>(static_cast<std::size_t>(k) * w / workers);
      const int last = static_cast<int>(static_cast<std::size_t>(k) * (w + 1) / workers);
      Eigen::MatrixXd& s = w == 0 ? upper : (partial[w] = Eigen::MatrixXd::Zero(n, n));
      // Row-major n x k with leading dimension k is column-major k x n: S += A^T' A' = A A^T.
      cblas_dsyrk(CblasColMajor, CblasUpper, CblasTrans, n, last - first, 1.0, a.data() + first, k, 1.0,
                  s.data(), static_cast<int>(s.rows()));
    }
  });
  for (std::size_t w = 1; w < workers; ++w) upper += partial[w];
  openblas_set_num_threads(saved);
}

void symmetrize_from_upper(Eigen::MatrixXd& s) { s.triangularView<Eigen::StrictlyLower>() = s.transpose(); }

}  // namespace matlas
