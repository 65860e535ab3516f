#include "gp/kernel.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/parallel.h"
#include "core/vector_math.h"

namespace matlas::gp {

double Kernel::operator()(const Eigen::Ref<const Eigen::VectorXd>& a,
                          const Eigen::Ref<const Eigen::VectorXd>& b) const {
  return std::exp(-(a - b).squaredNorm() / (lengthscale * lengthscale));
}

void validate(const Kernel& k) {
  if (!std::isfinite(k.lengthscale) || k.lengthscale <= 0)
    throw Error("kernel: lengthscale must be a finite positive number (got " + std::to_string(k.lengthscale) + ")");
  if (!std::isfinite(k.nugget) || k.nugget < 0)
    throw Error("kernel: nugget must be a finite number >= 0 (got " + std::to_string(k.nugget) + ")");
}

namespace {

/// Columns per block of the elementwise work below (on the workers; the blocks, and so every
/// value, do not depend on their number).
constexpr std::size_t kDistanceColumns = 128;

}  // namespace

void squared_distances(const Eigen::MatrixXd& X, Eigen::MatrixXd& D) {
  const Eigen::Index n = X.rows();
  D.resize(n, n);
  // Column-wise accumulation vectorises over i; the same expression for (i, j) and (j, i) keeps D
  // exactly symmetric because (a - b)^2 == (b - a)^2 in floating point.
  parallel_for_blocks(static_cast<std::size_t>(n), kDistanceColumns, [&](std::size_t first, std::size_t size) {
    const auto c0 = static_cast<Eigen::Index>(first), w = static_cast<Eigen::Index>(size);
    D.middleCols(c0, w).setZero();
    for (Eigen::Index d = 0; d < X.cols(); ++d)
      for (Eigen::Index j = c0; j < c0 + w; ++j) D.col(j).array() += (X.col(d).array() - X(j, d)).square();
  });
}

void covariance_from_squared_distances(const Eigen::MatrixXd& D2, const Kernel& k, Eigen::MatrixXd& K) {
  const Eigen::Index n = D2.rows();
  K.resize(n, D2.cols());
  const double scale = -1.0 / (k.lengthscale * k.lengthscale);
  const auto columns = static_cast<std::size_t>(K.cols());
  parallel_for_blocks(columns, kDistanceColumns, [&](std::size_t first, std::size_t size) {
    const auto c0 = static_cast<Eigen::Index>(first), w = static_cast<Eigen::Index>(size);
    K.middleCols(c0, w) = D2.middleCols(c0, w) * scale;
    exp_in_place(K.col(c0).data(), static_cast<std::size_t>(n * w));  // lane by lane: the same values in any split
  });
  parallel_for_blocks(columns, kDistanceColumns, [&](std::size_t first, std::size_t size) {
    for (auto j = static_cast<Eigen::Index>(first); j < static_cast<Eigen::Index>(first + size); ++j) {
      for (Eigen::Index i = j + 1; i < K.rows(); ++i) K(i, j) = K(j, i);
      K(j, j) += k.nugget;
    }
  });
}

Eigen::MatrixXd covariance_matrix(const Eigen::MatrixXd& X, const Kernel& k) {
  Eigen::MatrixXd D2, K;
  squared_distances(X, D2);
  covariance_from_squared_distances(D2, k, K);
  return K;
}

bool is_positive_definite(const Eigen::LLT<Eigen::MatrixXd>& llt) {
  return llt.info() == Eigen::Success && acceptable_cholesky_pivots(llt.matrixLLT().diagonal());
}

bool acceptable_cholesky_pivots(const Eigen::VectorXd& factor_diagonal) {
  const Eigen::ArrayXd pivots = factor_diagonal.array().square();
  if (pivots.size() == 0) return true;
  const double n = static_cast<double>(pivots.size());
  return pivots.minCoeff() > n * std::numeric_limits<double>::epsilon() * pivots.maxCoeff();
}

}  // namespace matlas::gp
