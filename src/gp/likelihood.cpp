#include "gp/likelihood.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "core/check.h"
#include "core/blas.h"
#include "core/tiled_cholesky.h"
#include "core/tiled_products.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/symmetric_eigen.h"
#include "core/vector_math.h"

namespace matlas::gp {

namespace {

std::string dims(Eigen::Index r, Eigen::Index c) { return std::to_string(r) + " x " + std::to_string(c); }

/// Columns per block of the elementwise n x n work below, on the workers (the blocks, and so
/// every value, do not depend on their number).
constexpr std::size_t kElementwiseColumns = 128;

/// body(j) for every column j of an n x n matrix, in blocks of columns on the workers.
void for_each_column(Eigen::Index n, const std::function<void(Eigen::Index)>& body) {
  parallel_for_blocks(static_cast<std::size_t>(n), kElementwiseColumns, [&](std::size_t first, std::size_t size) {
    for (auto j = static_cast<Eigen::Index>(first); j < static_cast<Eigen::Index>(first + size); ++j) body(j);
  });
}

/// The strict upper triangle of A made the transpose of its lower one.
void mirror_lower(Eigen::MatrixXd& A) {
  for_each_column(A.cols(), [&](Eigen::Index j) {
    for (Eigen::Index i = 0; i < j; ++i) A(i, j) = A(j, i);
  });
}

}  // namespace

std::shared_ptr<const GramFactor> gram_factor(const Eigen::MatrixXd& S) {
  if (S.rows() != S.cols() || S.rows() == 0)
    throw Error("likelihood: the Gram matrix must be square and non-empty (got " + dims(S.rows(), S.cols()) + ")");
  if (!S.allFinite()) throw Error("likelihood: the Gram matrix contains NaN or infinity");
  const double n = static_cast<double>(S.rows());
  auto f = std::make_shared<GramFactor>();
  f->sigma = S.trace() / n;
  if (!(f->sigma > 0))
    throw Error("likelihood: the Gram matrix has trace " + std::to_string(S.trace()) +
                " (all data rows equal, or not a Gram matrix)");
  // S~ = S / sigma has trace n; its eigen-decomposition gives R with S~ = R R^T. The solver reads
  // the lower triangle only, so a slightly asymmetric input is taken as symmetric.
  const SymmetricEigen eig = symmetric_eigen(S / f->sigma);
  const Eigen::VectorXd& lambda = eig.values;  // ascending
  const double top = lambda[lambda.size() - 1];
  if (lambda[0] < -1e-6 * top)
    throw Error("likelihood: the Gram matrix is not positive semidefinite (eigenvalue " + std::to_string(lambda[0]) +
                " vs largest " + std::to_string(top) + ", relative to tr(S)/n)");
  Eigen::Index first = 0;
  while (first < lambda.size() && lambda[first] <= 1e-13 * top) ++first;
  const Eigen::Index r = lambda.size() - first;
  MATLAS_CHECK_GT(r, Eigen::Index{0});  // lambda sums to n > 0, so the largest is kept
  f->R = eig.vectors.rightCols(r) * lambda.tail(r).cwiseSqrt().asDiagonal();
  return f;
}

LikelihoodProblem with_factor(const LikelihoodProblem& p) {
  LikelihoodProblem q = p;
  if (!q.factor) q.factor = gram_factor(q.gram);
  return q;
}

LikelihoodEvaluator::LikelihoodEvaluator(const LikelihoodProblem& p)
    : columns_(p.columns), kernel_(p.kernel), beta_(p.prior.complexity_weight) {
  validate(kernel_);
  if (!(beta_ > 0) || beta_ > 1)
    throw Error("likelihood: the complexity weight must be in (0, 1], got " + std::to_string(beta_));
  repulsion_ = p.prior.repulsion;
  radius_ = p.prior.radius;
  if (!(repulsion_ >= 0) || !std::isfinite(repulsion_))
    throw Error("likelihood: the repulsion weight must be finite and >= 0, got " + std::to_string(repulsion_));
  if (repulsion_ > 0 && (!(radius_ > 0) || !std::isfinite(radius_)))
    throw Error("likelihood: the repulsion radius must be finite and > 0, got " + std::to_string(radius_));
  precision_ = p.prior.precision;
  if (!(precision_ >= 0) || !std::isfinite(precision_))
    throw Error("likelihood: the latent precision must be finite and >= 0, got " + std::to_string(precision_));
  if (!std::isfinite(columns_) || columns_ <= 0)
    throw Error("likelihood: the number of data columns must be finite and > 0 (got " + std::to_string(columns_) + ")");
  factor_ = p.factor ? p.factor : gram_factor(p.gram);
  MATLAS_CHECK_EQ(factor_->R.rows(), p.gram.rows());
}

double LikelihoodEvaluator::normalized(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient) {
  const Eigen::MatrixXd& R = factor_->R;
  const Eigen::Index n = R.rows();
  if (X.rows() != n)
    throw Error("likelihood: " + std::to_string(X.rows()) + " latent points for a Gram matrix of " +
                std::to_string(n) + " items");
  if (!X.allFinite()) throw Error("likelihood: latent points contain NaN or infinity");
  const double nd = static_cast<double>(n);
  const double inv_l2 = 1.0 / (kernel_.lengthscale * kernel_.lengthscale);

  // K = C + delta I, exactly symmetric (off-diagonal entries of K are those of C).
  squared_distances(X, D2_);
  covariance_from_squared_distances(D2_, kernel_, K_);

  // The dense algebra goes through OpenBLAS, whose kernels are vectorised for this processor
  // (Eigen's are compiled for baseline x86-64 here): K^-1 from the Cholesky factor, then
  // B = K^-1 R in one dsymm (docs/GP.md, "Evaluation"; two triangular solves took twice as long).
  const blas::Library& blas = blas::openblas();
  const int nn = static_cast<int>(n), r = static_cast<int>(R.cols());
  L_.resize(n, n);
  for_each_column(n, [&](Eigen::Index j) { L_.col(j) = K_.col(j); });
  int info = blas::tiled_cholesky(nn, L_.data(), nn);
  if (info != 0 || !acceptable_cholesky_pivots(L_.diagonal()))
    throw Error("likelihood: the covariance matrix of the latent points is not positive definite (duplicate "
                "latent points with nugget " + std::to_string(kernel_.nugget) + "?); use a nugget > 0");
  const double log_det = 2.0 * L_.diagonal().array().log().sum();
  MATLAS_CHECK(std::isfinite(log_det), "log|K| after an accepted Cholesky factor");
  Kinv_.resize(n, n);
  W_.resize(n, n);
  info = blas::tiled_inverse_from_cholesky(nn, L_.data(), nn, W_.data(), Kinv_.data(), nn);  // lower triangle of K^-1
  if (info != 0) throw Error("likelihood: inverting the covariance matrix failed (LAPACK info " + std::to_string(info) + ")");

  // t = tr(K^-1 S~) = sum(R o B) with B = K^-1 R: K^-1 made whole, then one product in column
  // blocks over the workers (with OpenBLAS single-threaded, one dsymm left the other cores idle).
  mirror_lower(Kinv_);
  B_.resize(n, r);
  blas::tiled_product(nn, r, nn, 1.0, Kinv_.data(), nn, R.data(), nn, B_.data(), nn);
  const double t = (R.array() * B_.array()).sum();
  if (!(t > 0) || !std::isfinite(t))
    throw Error("likelihood: tr(K^-1 S) is not positive (" + std::to_string(t) + "): K is too ill-conditioned");
  double value = -beta_ * log_det - nd * std::log(t / nd) - nd;
  // The repulsive prior: lambda sum_{i<j} log(1 - e^{-u} + floor), u = |x_i - x_j|^2 / rho^2, and
  // (when asked) its gradient, d/dx_i = sum_j F_ij (x_i - x_j) with F_ij = lambda e^{-u} /
  // (1 - e^{-u} + floor) 2 / rho^2, F kept for the gradient below. Over whole columns at a
  // time, with one expm1 per pair for both, so that libmvec's vector functions do the work;
  // pairs with u >= 40 (e^-40) and the diagonal contribute exactly nothing.
  const double inv_r2 = 1.0 / (radius_ * radius_);
  const Eigen::Index q = X.cols();
  if (repulsion_ > 0) {
    const double cutoff = 40.0 / inv_r2;  // u >= 40 <=> d^2 >= 40 rho^2
    const double scale = repulsion_ * 2.0 * inv_r2;
    E_.resize(n, n);
    Logs_.resize(n, n);
    if (gradient != nullptr) F_.resize(n, n);
    // In fixed blocks of columns on the workers; their sums added in order (the same bits with
    // any number of workers).
    constexpr Eigen::Index kBlock = 128;
    const auto blocks = static_cast<std::size_t>((n + kBlock - 1) / kBlock);
    sums_.assign(blocks, 0.0);
    const auto block = [&](std::size_t b) {
      const Eigen::Index c0 = static_cast<Eigen::Index>(b) * kBlock, w = std::min(kBlock, n - c0);
      const auto size = static_cast<std::size_t>(n * w);
      E_.middleCols(c0, w) = D2_.middleCols(c0, w) * -inv_r2;
      expm1_in_place(E_.col(c0).data(), size);  // e^{-u} - 1
      Logs_.middleCols(c0, w) = kRepulsionFloor - E_.middleCols(c0, w).array();
      log_in_place(Logs_.col(c0).data(), size);
      double sum = 0.0;
      for (Eigen::Index j = c0; j < c0 + w; ++j)
        for (Eigen::Index i = j + 1; i < n; ++i) sum += D2_(i, j) < cutoff ? Logs_(i, j) : 0.0;
      sums_[b] = sum;
      if (gradient == nullptr) return;
      const auto e = E_.middleCols(c0, w).array();
      F_.middleCols(c0, w) =
          (D2_.middleCols(c0, w).array() < cutoff).select(scale * (1.0 + e) / (kRepulsionFloor - e), 0.0);
      for (Eigen::Index j = c0; j < c0 + w; ++j) F_(j, j) = 0.0;
    };
    parallel_for_each(0, blocks, block);
    double sum = 0.0;
    for (const double s : sums_) sum += s;
    value += repulsion_ * sum;
  }
  MATLAS_CHECK(std::isfinite(value), "the likelihood's determinant, trace and barrier terms");
  value -= 0.5 * precision_ * X.squaredNorm();
  if (gradient == nullptr) return value;

  // dl/dK = G = -beta K^-1 + (n/t) K^-1 S~ K^-1, and K^-1 S~ K^-1 = B B^T.
  G_.resize(n, n);
  blas::tiled_lower_gram(nn, r, nd / t, B_.data(), nn, 0.0, G_.data(), nn);
  for_each_column(n, [&](Eigen::Index j) { G_.col(j).tail(n - j) -= beta_ * Kinv_.col(j).tail(n - j); });
  mirror_lower(G_);
  // dl/dx_i = sum_j (G_ij + G_ji) dK_ij/dx_i with dK_ij/dx_i = -2 (x_i - x_j) K_ij / l^2 (i != j),
  // i.e. dl/dx_i = sum_j M_ij (x_j - x_i) with M = (4/l^2) G o K; the prior's forces add -F to M
  // (d/dx_i = sum_j F_ij (x_i - x_j)). So dl/dX = M X - diag(M 1) X - gamma X, one product (the
  // diagonal of M cancels in the difference, so it need not be removed).
  for_each_column(n, [&](Eigen::Index j) {
    G_.col(j).array() *= K_.col(j).array() * (4.0 * inv_l2);
    if (repulsion_ > 0) G_.col(j) -= F_.col(j);
  });
  gradient->resize(n, q);
  blas.dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nn, static_cast<int>(q), nn, 1.0, G_.data(), nn, X.data(), nn,
             0.0, gradient->data(), nn);
  *gradient -= G_.rowwise().sum().asDiagonal() * X;
  *gradient -= precision_ * X;
  return value;
}

double LikelihoodEvaluator::to_log_likelihood(double normalized_value) const {
  const double n = static_cast<double>(factor_->R.rows());
  return columns_ * (normalized_value - n * std::log(factor_->sigma / columns_));
}

double LikelihoodEvaluator::operator()(const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient) {
  const double value = to_log_likelihood(normalized(X, gradient));
  if (gradient != nullptr) *gradient *= columns_;
  return value;
}

double log_likelihood(const LikelihoodProblem& p, const Eigen::MatrixXd& X, Eigen::MatrixXd* gradient) {
  LikelihoodEvaluator evaluator(p);
  return evaluator(X, gradient);
}

}  // namespace matlas::gp
