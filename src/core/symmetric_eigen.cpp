#include "core/symmetric_eigen.h"

#include <string>
#include <vector>

#include "core/blas.h"
#include "core/error.h"

namespace matlas {

SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& a) {
  if (a.rows() != a.cols())
    throw Error("symmetric_eigen: the matrix is " + std::to_string(a.rows()) + " x " + std::to_string(a.cols()) +
                ", not square");
  if (!a.allFinite()) throw Error("symmetric_eigen: the matrix contains NaN or infinity");
  SymmetricEigen e;
  e.vectors = a;
  const int n = static_cast<int>(a.rows());
  e.values.resize(n);
  if (n == 0) return e;
  const blas::Library& lib = blas::openblas();
  int info = 0, lwork = -1, liwork = -1, iwork_size = 0;
  double work_size = 0;
  lib.dsyevd("V", "L", &n, e.vectors.data(), &n, e.values.data(), &work_size, &lwork, &iwork_size, &liwork, &info);
  if (info != 0) throw Error("symmetric_eigen: LAPACK dsyevd's workspace query failed (info " + std::to_string(info) + ")");
  lwork = static_cast<int>(work_size);
  liwork = iwork_size;
  std::vector<double> work(static_cast<std::size_t>(lwork));
  std::vector<int> iwork(static_cast<std::size_t>(liwork));
  lib.dsyevd("V", "L", &n, e.vectors.data(), &n, e.values.data(), work.data(), &lwork, iwork.data(), &liwork, &info);
  if (info != 0)
    throw Error("symmetric_eigen: LAPACK dsyevd did not converge for a " + std::to_string(n) + " x " +
                std::to_string(n) + " matrix (info " + std::to_string(info) + ")");
  return e;
}

}  // namespace matlas
