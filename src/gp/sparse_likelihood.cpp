#include "gp/sparse_likelihood.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/blas.h"
#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/vector_math.h"
#include "gp/sparse_repulsion.h"

namespace matlas::gp {

namespace {

/// C = alpha op(A) op(B) + beta C through OpenBLAS (C is resized; Eigen's own kernels are compiled
/// for baseline x86-64 here, docs/GP.md "Evaluation"). OpenBLAS runs single-threaded (core/blas.h):
/// a product of more than kSplitFlops is split by the longer side of C over the worker threads.
void dense_gemm(bool ta, bool tb, double alpha, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double beta,
          Eigen::MatrixXd& C) {
  const Eigen::Index rows = ta ? A.cols() : A.rows(), inner = ta ? A.rows() : A.cols();
  const Eigen::Index cols = tb ? B.rows() : B.cols();
  MATLAS_CHECK((tb ? B.cols() : B.rows()) == inner);
  if (beta == 0.0) C.resize(rows, cols);
  MATLAS_CHECK(C.rows() == rows && C.cols() == cols);
  if (rows == 0 || cols == 0) return;
  if (inner == 0) {
    C *= beta;
    return;
  }
  const auto lda = static_cast<int>(A.rows()), ldb = static_cast<int>(B.rows()), ldc = static_cast<int>(C.rows());
  // C's rows [r0, r1) and columns [c0, c1).
  const auto part = [&](Eigen::Index r0, Eigen::Index r1, Eigen::Index c0, Eigen::Index c1) {
    const double* a = ta ? A.data() + r0 * lda : A.data() + r0;
    const double* b = tb ? B.data() + c0 : B.data() + c0 * ldb;
    blas::openblas().dgemm(CblasColMajor, ta ? CblasTrans : CblasNoTrans, tb ? CblasTrans : CblasNoTrans,
                           static_cast<int>(r1 - r0), static_cast<int>(c1 - c0), static_cast<int>(inner), alpha, a,
                           lda, b, ldb, beta, C.data() + r0 + c0 * ldc, ldc);
  };
  constexpr double kSplitFlops = 2e7;  // about a millisecond
  const double flops = 2.0 * static_cast<double>(rows) * static_cast<double>(cols) * static_cast<double>(inner);
  if (flops < kSplitFlops || worker_count() < 2) {
    part(0, rows, 0, cols);
    return;
  }
  const bool by_rows = rows >= cols;
  parallel_for(0, static_cast<std::size_t>(by_rows ? rows : cols), [&](std::size_t begin, std::size_t end) {
    const auto b = static_cast<Eigen::Index>(begin), e = static_cast<Eigen::Index>(end);
    if (by_rows)
      part(b, e, 0, cols);
    else
      part(0, rows, b, e);
  }, 32);
}

/// L^-1 of the lower Cholesky factor of a small SPD matrix; log|A| into *log_det. Throws
/// matlas::Error (naming `what`) if A is not positive definite.
Eigen::MatrixXd inverse_cholesky_factor(const Eigen::MatrixXd& A, double* log_det, const char* what) {
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (!is_positive_definite(llt))
    throw Error(std::string("sparse likelihood: ") + what + " is not positive definite");
  MATLAS_CHECK_EQ(A.rows(), A.cols());
  if (log_det != nullptr) {
    *log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
    MATLAS_CHECK(std::isfinite(*log_det), "log|A| after an accepted Cholesky factor");
  }
  Eigen::MatrixXd inv = Eigen::MatrixXd::Identity(A.rows(), A.cols());
  llt.matrixL().solveInPlace(inv);
  return inv;
}

/// Columns of an orthonormal basis of the range of M (n x k, k <= n).
Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& M) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
  return qr.householderQ() * Eigen::MatrixXd::Identity(M.rows(), M.cols());
}

}  // namespace

LowRankGram low_rank_gram(const Eigen::MatrixXd& S, int rank, std::uint64_t seed) {
  if (S.rows() != S.cols() || S.rows() == 0) throw Error("low_rank_gram: the Gram matrix must be square and non-empty");
  if (!S.allFinite()) throw Error("low_rank_gram: the Gram matrix contains NaN or infinity");
  if (rank < 1) throw Error("low_rank_gram: the rank must be >= 1 (got " + std::to_string(rank) + ")");
  const Eigen::Index n = S.rows();
  const Eigen::Index r = std::min<Eigen::Index>(rank, n);
  Eigen::MatrixXd basis;  // n x k orthonormal, its span holds the leading eigenvectors
  if (n <= 400 || 4 * r >= n) {
    basis = Eigen::MatrixXd::Identity(n, n);
  } else {
    const Eigen::Index k = std::min<Eigen::Index>(n, r + 16);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    Eigen::MatrixXd omega(n, k);
    for (Eigen::Index j = 0; j < k; ++j)
      for (Eigen::Index i = 0; i < n; ++i) omega(i, j) = normal(rng);
    Eigen::MatrixXd product;
    dense_gemm(false, false, 1.0, S, omega, 0.0, product);
    basis = orthonormal_basis(product);
    for (int it = 0; it < 4; ++it) {
      dense_gemm(false, false, 1.0, S, basis, 0.0, product);
      basis = orthonormal_basis(product);
    }
  }
  Eigen::MatrixXd SB;
  dense_gemm(false, false, 1.0, S, basis, 0.0, SB);
  Eigen::MatrixXd T;
  dense_gemm(true, false, 1.0, basis, SB, 0.0, T);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (T + T.transpose()));
  if (eig.info() != Eigen::Success) throw Error("low_rank_gram: eigen-decomposition failed");
  const Eigen::Index k = T.rows();
  LowRankGram out;
  Eigen::MatrixXd vectors(k, r);
  Eigen::VectorXd scales(r);
  for (Eigen::Index c = 0; c < r; ++c) {  // eigenvalues ascend: take them from the top
    vectors.col(c) = eig.eigenvectors().col(k - 1 - c);
    scales[c] = std::sqrt(std::max(0.0, eig.eigenvalues()[k - 1 - c]));
  }
  dense_gemm(false, false, 1.0, basis, vectors, 0.0, out.factor);
  out.factor *= scales.asDiagonal();
  out.residual = std::max(0.0, S.trace() - out.factor.squaredNorm());
  return out;
}

SparseLikelihoodEvaluator::SparseLikelihoodEvaluator(const SparseProblem& p)
    : columns_(p.columns), kernel_(p.kernel), beta_(p.prior.complexity_weight), jitter_(p.jitter) {
  validate(kernel_);
  repulsion_ = p.prior.repulsion;
  radius_ = p.prior.radius;
  precision_ = p.prior.precision;
  if (!(beta_ > 0) || beta_ > 1)
    throw Error("sparse likelihood: the complexity weight must be in (0, 1], got " + std::to_string(beta_));
  if (!(repulsion_ >= 0) || !std::isfinite(repulsion_) || (repulsion_ > 0 && (!(radius_ > 0) || !std::isfinite(radius_))))
    throw Error("sparse likelihood: the repulsion must be finite and >= 0 with a finite radius > 0");
  if (!(precision_ >= 0) || !std::isfinite(precision_))
    throw Error("sparse likelihood: the latent precision must be finite and >= 0");
  if (!(jitter_ >= 0) || !std::isfinite(jitter_)) throw Error("sparse likelihood: the jitter must be finite and >= 0");
  const Eigen::MatrixXd& Y = p.data.factor;
  if (Y.rows() == 0 || Y.cols() == 0) throw Error("sparse likelihood: the data factor is empty");
  if (!Y.allFinite()) throw Error("sparse likelihood: the data factor contains NaN or infinity");
  if (!(p.data.residual >= 0) || !std::isfinite(p.data.residual))
    throw Error("sparse likelihood: the residual trace must be finite and >= 0");
  if (!std::isfinite(columns_) || columns_ <= 0)
    throw Error("sparse likelihood: the number of data columns must be finite and > 0");
  const double n = static_cast<double>(Y.rows());
  sigma_ = (Y.squaredNorm() + p.data.residual) / n;
  if (!(sigma_ > 0)) throw Error("sparse likelihood: the Gram matrix has zero trace (all data rows equal)");
  Y_ = Y / std::sqrt(sigma_);
  eps_ = p.data.residual / (sigma_ * n);
  std::vector<std::vector<Eigen::Index>> singletons(static_cast<std::size_t>(Y.rows()));
  for (Eigen::Index i = 0; i < Y.rows(); ++i) singletons[static_cast<std::size_t>(i)] = {i};
  set_blocks(std::move(singletons));
}

void SparseLikelihoodEvaluator::apply_block_inverse(const Eigen::MatrixXd& M, Eigen::MatrixXd& out) const {
  MATLAS_CHECK_EQ(M.rows(), Y_.rows());
  MATLAS_CHECK_EQ(block_inv_.size(), blocks_.size());
  if (diagonal_) {
    out.noalias() = lambda_inv_.asDiagonal() * M;
    return;
  }
  out.resize(M.rows(), M.cols());
  Eigen::MatrixXd Mb;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const std::vector<Eigen::Index>& idx = blocks_[k];
    const auto s = static_cast<Eigen::Index>(idx.size());
    Mb.resize(s, M.cols());
    for (Eigen::Index a = 0; a < s; ++a) Mb.row(a) = M.row(idx[a]);
    const auto L = block_inv_[k].triangularView<Eigen::Lower>();
    Mb = L * Mb;
    Mb = L.transpose() * Mb;
    for (Eigen::Index a = 0; a < s; ++a) out.row(idx[a]) = Mb.row(a);
  }
}

void SparseLikelihoodEvaluator::apply_inverse(const Eigen::MatrixXd& M, Eigen::MatrixXd& out) const {
  Eigen::MatrixXd UtM;
  dense_gemm(true, false, 1.0, U_, M, 0.0, UtM);
  apply_block_inverse(M, out);
  dense_gemm(false, false, -1.0, U_, UtM, 1.0, out);
}

void SparseLikelihoodEvaluator::set_blocks(std::vector<std::vector<Eigen::Index>> blocks) {
  const Eigen::Index n = Y_.rows();
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  Eigen::Index total = 0;
  for (const auto& b : blocks) {
    if (b.empty()) throw Error("sparse likelihood: an empty block");
    for (Eigen::Index i : b) {
      if (i < 0 || i >= n || seen[static_cast<std::size_t>(i)])
        throw Error("sparse likelihood: the blocks must be a partition of the items");
      seen[static_cast<std::size_t>(i)] = 1;
      ++total;
    }
  }
  if (total != n) throw Error("sparse likelihood: the blocks must be a partition of the items");
  blocks_ = std::move(blocks);
  diagonal_ = blocks_.size() == static_cast<std::size_t>(n);
  block_inv_.assign(blocks_.size(), Eigen::MatrixXd());
  block_cov_.assign(blocks_.size(), Eigen::MatrixXd());
}

double SparseLikelihoodEvaluator::normalized(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z,
                                             Eigen::MatrixXd* grad_X, Eigen::MatrixXd* grad_Z) {
  const Eigen::Index n = Y_.rows(), m = Z.rows(), q = X.cols();
  if (X.rows() != n)
    throw Error("sparse likelihood: " + std::to_string(X.rows()) + " latent points for " + std::to_string(n) + " items");
  if (m == 0 || Z.cols() != q) throw Error("sparse likelihood: the inducing points must be m x q with m >= 1");
  if (!X.allFinite() || !Z.allFinite()) throw Error("sparse likelihood: latent or inducing points contain NaN or infinity");
  const double nd = static_cast<double>(n);

  const double log_det = factorize(X, Z);

  // t = tr(K~^-1 Y Y^T) + eps tr(K~^-1), tr(K~^-1) = sum_b |L_b^-1|^2 - |U|^2.
  apply_inverse(Y_, B_);
  double trace_inv = -U_.squaredNorm();
  if (diagonal_)
    trace_inv += lambda_inv_.sum();
  else
    for (const Eigen::MatrixXd& Li : block_inv_) trace_inv += Li.triangularView<Eigen::Lower>().toDenseMatrix().squaredNorm();
  const double t = (Y_.array() * B_.array()).sum() + eps_ * trace_inv;
  if (!(t > 0) || !std::isfinite(t))
    throw Error("sparse likelihood: tr(K^-1 S) is not positive (" + std::to_string(t) + "): K is too ill-conditioned");
  double value = -beta_ * log_det - nd * std::log(t / nd) - nd;
  MATLAS_CHECK(std::isfinite(value), "the sparse likelihood's determinant and trace terms");
  if (grad_X != nullptr) grad_X->setZero(n, q);
  value += sparse_repulsion(X, repulsion_, radius_, grad_X);
  value -= 0.5 * precision_ * X.squaredNorm();
  if (grad_X == nullptr && grad_Z == nullptr) return value;

  add_gradient(X, Z, t, grad_X, grad_Z);
  return value;
}

double SparseLikelihoodEvaluator::factorize_diagonal() {
  // FITC: Lambda_ii = C_ii - |V_i|^2 + delta with C_ii = 1, and A = I + W W^T, W = V Lambda^-1/2.
  const Eigen::Index m = V_.rows();
  const Eigen::ArrayXd lambda = (1.0 + kernel_.nugget) - V_.colwise().squaredNorm().transpose().array();
  if (!(lambda > 0).all()) throw Error("sparse likelihood: a block of the covariance (nugget 0?) is not positive definite");
  lambda_inv_ = lambda.inverse().matrix();
  const Eigen::MatrixXd W = V_ * lambda_inv_.cwiseSqrt().asDiagonal();
  A_.setIdentity(m, m);
  dense_gemm(false, true, 1.0, W, W, 1.0, A_);
  return lambda.log().sum();
}

double SparseLikelihoodEvaluator::factorize_blocks(const Eigen::MatrixXd& X) {
  const Eigen::Index m = V_.rows(), q = X.cols();
  A_.setIdentity(m, m);
  double log_det = 0;
  Eigen::MatrixXd Vb, Wb;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const std::vector<Eigen::Index>& idx = blocks_[k];
    const auto s = static_cast<Eigen::Index>(idx.size());
    Vb.resize(m, s);
    Eigen::MatrixXd Xb(s, q);
    for (Eigen::Index a = 0; a < s; ++a) Vb.col(a) = V_.col(idx[a]), Xb.row(a) = X.row(idx[a]);
    Eigen::MatrixXd& Cb = block_cov_[k];
    Cb = covariance_matrix(Xb, Kernel{kernel_.lengthscale, 0.0});
    Eigen::MatrixXd Lambda = Cb;
    Lambda.noalias() -= Vb.transpose() * Vb;
    Lambda.diagonal().array() += kernel_.nugget;
    double log_det_b = 0;
    block_inv_[k] = inverse_cholesky_factor(Lambda, &log_det_b, "a block of the covariance (nugget 0?)");
    log_det += log_det_b;
    Wb.noalias() = block_inv_[k].triangularView<Eigen::Lower>() * Vb.transpose();  // L_b^-1 V_b^T
    A_.noalias() += Wb.transpose() * Wb;
  }
  return log_det;
}

double SparseLikelihoodEvaluator::factorize(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z) {
  const Eigen::Index n = Y_.rows(), m = Z.rows(), q = X.cols();
  const double inv_l2 = 1.0 / (kernel_.lengthscale * kernel_.lengthscale);
  // C_nm (no nugget) and C_mm + jitter I.
  Cnm_.setZero(n, m);
  for (Eigen::Index d = 0; d < q; ++d)
    for (Eigen::Index j = 0; j < m; ++j) Cnm_.col(j).array() += (X.col(d).array() - Z(j, d)).square();
  Cnm_ *= -inv_l2;
  exp_in_place(Cnm_.data(), static_cast<std::size_t>(Cnm_.size()));
  Eigen::MatrixXd D2m;
  squared_distances(Z, D2m);
  covariance_from_squared_distances(D2m, Kernel{kernel_.lengthscale, jitter_}, Cmm_);
  Lminv_ = inverse_cholesky_factor(Cmm_, nullptr, "the inducing points' covariance (coincident inducing points?)");

  // V = L_m^-1 C_mn (Q = V^T V). Per block b: Lambda_b = C_bb - Q_bb + delta I (the Schur
  // complement plus the nugget: positive definite) = L_b L_b^T; L_b^-1 kept for Lambda_b^-1.
  dense_gemm(false, true, 1.0, Lminv_, Cnm_, 0.0, V_);
  double log_det = diagonal_ ? factorize_diagonal() : factorize_blocks(X);
  // A = I + V Lambda^-1 V^T (m x m), log|K~| = log|A| + log|Lambda|; K~^-1 = Lambda^-1 - U U^T
  // with U = Lambda^-1 V^T L_A^-T.
  double log_det_A = 0;
  const Eigen::MatrixXd LAinv = inverse_cholesky_factor(A_, &log_det_A, "I + V Lambda^-1 V^T");
  log_det += log_det_A;
  dense_gemm(true, true, 1.0, V_, LAinv, 0.0, H1_);
  apply_block_inverse(H1_, U_);
  return log_det;
}

void SparseLikelihoodEvaluator::add_gradient(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z, double t,
                                             Eigen::MatrixXd* grad_X, Eigen::MatrixXd* grad_Z) {
  const double nd = static_cast<double>(Y_.rows()), inv_l2 = 1.0 / (kernel_.lengthscale * kernel_.lengthscale);
  // dl/dK~ = G = -beta K~^-1 + (n/t) (B B^T + eps K~^-2). K~ = Q + blockdiag(C - Q) + delta I, so
  // dl = tr(G' dQ) + sum_b tr(G_bb dC_bb) with G' = G - blockdiag(G), and with
  // P^T = C_nm C_mm^-1 = V^T L_m^-1:  dl/dC_nm = 2 G' P^T = 2 W,  dl/dC_mm = -P G' P^T = -P W.
  dense_gemm(true, false, 1.0, V_, Lminv_, 0.0, Pt_);
  apply_inverse(Pt_, H1_);
  const double c = nd / t;
  Eigen::MatrixXd BtP;
  dense_gemm(true, false, 1.0, B_, Pt_, 0.0, BtP);
  W_ = -beta_ * H1_;
  dense_gemm(false, false, c, B_, BtP, 1.0, W_);
  Eigen::MatrixXd UtU;
  if (eps_ > 0) {
    apply_inverse(H1_, H2_);
    W_ += (c * eps_) * H2_;
    dense_gemm(true, false, 1.0, U_, U_, 0.0, UtU);
  }
  if (diagonal_)
    add_diagonal_terms(c, UtU);
  else
    add_block_terms(X, c, UtU, grad_X);
  Eigen::MatrixXd M;
  dense_gemm(true, false, 1.0, Pt_, W_, 0.0, M);
  M = 0.5 * (M + M.transpose());

  // Through the kernel: with A = (4/l^2) W o C_nm, dl/dX = A Z - diag(A 1) X and the C_nm part of
  // dl/dZ = A^T X - diag(A^T 1) Z; the C_mm part, with G_mm = -M, as in the dense gradient.
  W_.array() *= Cnm_.array() * (4.0 * inv_l2);
  if (grad_X != nullptr) {
    dense_gemm(false, false, 1.0, W_, Z, 1.0, *grad_X);
    *grad_X -= W_.rowwise().sum().asDiagonal() * X;
    *grad_X -= precision_ * X;
  }
  if (grad_Z != nullptr) {
    dense_gemm(true, false, 1.0, W_, X, 0.0, *grad_Z);
    *grad_Z -= W_.colwise().sum().transpose().asDiagonal() * Z;
    Eigen::MatrixXd Amm = M.array() * Cmm_.array() * (-4.0 * inv_l2);
    Amm.diagonal().setZero();
    *grad_Z += Amm * Z;
    *grad_Z -= Amm.rowwise().sum().asDiagonal() * Z;
  }
}

void SparseLikelihoodEvaluator::add_diagonal_terms(double c, const Eigen::MatrixXd& UtU) {
  // add_block_terms with singleton blocks (FITC): G_ii = -beta (1/Lambda_ii - |U_i|^2) + c (|B_i|^2
  // + eps (1/Lambda_ii^2 - 2 |U_i|^2 / Lambda_ii + U_i U^T U U_i^T)); no C_bb term (C_ii = 1).
  const Eigen::ArrayXd linv = lambda_inv_.array(), uu = U_.rowwise().squaredNorm().array();
  Eigen::ArrayXd g = -beta_ * (linv - uu) + c * B_.rowwise().squaredNorm().array();
  if (eps_ > 0) {
    Eigen::MatrixXd UQ;
    dense_gemm(false, false, 1.0, U_, UtU, 0.0, UQ);
    g += (c * eps_) * (linv.square() - 2.0 * linv * uu + (UQ.array() * U_.array()).rowwise().sum());
  }
  W_ -= g.matrix().asDiagonal() * Pt_;
}

void SparseLikelihoodEvaluator::add_block_terms(const Eigen::MatrixXd& X, double c, const Eigen::MatrixXd& UtU,
                                                Eigen::MatrixXd* grad_X) {
  const Eigen::Index m = U_.cols(), q = X.cols();
  const double inv_l2 = 1.0 / (kernel_.lengthscale * kernel_.lengthscale);
  // The blocks of G: -beta (Lambda_b^-1 - U_b U_b^T) + c (B_b B_b^T + eps (K~^-2)_bb), with
  // (K~^-2)_bb = Lambda_b^-2 - Lambda_b^-1 U_b U_b^T - U_b U_b^T Lambda_b^-1 + U_b (U^T U) U_b^T.
  Eigen::MatrixXd Gb, Ub, Bb, Pb, Linv, LU;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const std::vector<Eigen::Index>& idx = blocks_[k];
    const auto s = static_cast<Eigen::Index>(idx.size());
    Ub.resize(s, m), Bb.resize(s, B_.cols()), Pb.resize(s, m);
    for (Eigen::Index a = 0; a < s; ++a) Ub.row(a) = U_.row(idx[a]), Bb.row(a) = B_.row(idx[a]), Pb.row(a) = Pt_.row(idx[a]);
    const Eigen::MatrixXd L = block_inv_[k].triangularView<Eigen::Lower>();
    Linv.noalias() = L.transpose() * L;  // Lambda_b^-1
    const Eigen::MatrixXd UUt = Ub * Ub.transpose();
    Gb = -beta_ * (Linv - UUt);
    Gb.noalias() += c * (Bb * Bb.transpose());
    if (eps_ > 0) {
      LU.noalias() = Linv * UUt;
      Gb += (c * eps_) * (Linv * Linv - LU - LU.transpose() + Ub * UtU * Ub.transpose());
    }
    const Eigen::MatrixXd GP = Gb * Pb;
    for (Eigen::Index a = 0; a < s; ++a) W_.row(idx[a]) -= GP.row(a);
    if (grad_X != nullptr && s > 1) {  // sum_b tr(G_bb dC_bb), as the dense gradient
      const Eigen::MatrixXd Mb = Gb.cwiseProduct(block_cov_[k]) * (4.0 * inv_l2);
      Eigen::MatrixXd Xb(s, q);
      for (Eigen::Index a = 0; a < s; ++a) Xb.row(a) = X.row(idx[a]);
      const Eigen::MatrixXd gb = Mb * Xb - Mb.rowwise().sum().asDiagonal() * Xb;
      for (Eigen::Index a = 0; a < s; ++a) grad_X->row(idx[a]) += gb.row(a);
    }
  }
}

double SparseLikelihoodEvaluator::to_log_likelihood(double normalized_value) const {
  const double n = static_cast<double>(Y_.rows());
  return columns_ * (normalized_value - n * std::log(sigma_ / columns_));
}

std::vector<Eigen::Index> farthest_point_indices(const Eigen::MatrixXd& X, int m) {
  const Eigen::Index n = X.rows();
  if (n == 0 || m < 1) throw Error("farthest_point_subset: need points and m >= 1");
  const Eigen::Index count = std::min<Eigen::Index>(m, n);
  MATLAS_CHECK(X.allFinite(), "farthest points of finite latent points");
  const Eigen::RowVectorXd centroid = X.colwise().mean();
  Eigen::Index next = 0;
  (X.rowwise() - centroid).rowwise().squaredNorm().minCoeff(&next);
  Eigen::VectorXd nearest = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  std::vector<Eigen::Index> chosen;
  for (Eigen::Index k = 0; k < count; ++k) {
    chosen.push_back(next);
    nearest = nearest.cwiseMin((X.rowwise() - X.row(next)).rowwise().squaredNorm());
    nearest.maxCoeff(&next);
  }
  return chosen;
}

Eigen::MatrixXd farthest_point_subset(const Eigen::MatrixXd& X, int m) {
  const std::vector<Eigen::Index> chosen = farthest_point_indices(X, m);
  Eigen::MatrixXd Z(static_cast<Eigen::Index>(chosen.size()), X.cols());
  for (std::size_t k = 0; k < chosen.size(); ++k) Z.row(static_cast<Eigen::Index>(k)) = X.row(chosen[k]);
  return Z;
}

}  // namespace matlas::gp
