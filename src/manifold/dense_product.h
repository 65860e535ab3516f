#pragma once
// Large dense matrix products through OpenBLAS (vectorised for the CPU it runs on, core/blas.h),
// split over the workers, for the batched queries of map layers: Eigen's own product is compiled
// for baseline x86-64 here and single-threaded.
#include <Eigen/Core>

namespace matlas {

/// a * b (column-major, double).
Eigen::MatrixXd blas_product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace matlas
