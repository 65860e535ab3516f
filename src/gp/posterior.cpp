#include "gp/posterior.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/SVD>

#include "core/check.h"
#include "core/blas.h"
#include "core/huge_pages.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/vector_math.h"

namespace matlas::gp {

GpPosterior::GpPosterior(Eigen::MatrixXd X, Kernel k) : X_(std::move(X)), kernel_(k) {
  validate(kernel_);
  if (X_.rows() == 0 || X_.cols() == 0) throw Error("GP posterior: no latent points (X is empty)");
  if (!X_.allFinite()) throw Error("GP posterior: latent points contain NaN or infinity");
  llt_.compute(covariance_matrix(X_, kernel_));
  MATLAS_CHECK_EQ(llt_.matrixLLT().rows(), X_.rows());
  if (!is_positive_definite(llt_))
    throw Error("GP posterior: the covariance matrix of the " + std::to_string(X_.rows()) +
                " latent points is not positive definite (duplicate points with nugget " +
                std::to_string(kernel_.nugget) + "?); use a nugget > 0");
  // Taper radii: a tenth of a lengthscale, at most half the distance to the nearest other point
  // (so no two tapers overlap and w(x_i) = e_i exactly); 0 for exact duplicates.
  const Eigen::Index n = X_.rows();
  taper_radius_ = Eigen::VectorXd::Constant(n, 0.1 * kernel_.lengthscale);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != i) taper_radius_[i] = std::min(taper_radius_[i], 0.5 * (X_.row(i) - X_.row(j)).norm());
}

namespace {

/// phi(distance) for a taper of radius r: 1 at the point, (1 - t^2)^2 with t = distance / r
/// inside, 0 outside.
double taper_weight(double r, double distance) {
  if (distance == 0.0) return 1.0;
  if (!(distance < r)) return 0.0;
  const double t = distance / r;
  return (1.0 - t * t) * (1.0 - t * t);
}

/// k(x) with the tapered nugget for `count` points (points + j * q: point j's q coordinates) into
/// the columns of `out` (n x count, contiguous): the squared distances, one exp over the whole
/// block, then the nugget's taper where a point is within a data point's radius (few points).
/// noise[j] (when given) receives nugget * sum_i phi_i(x_j)^2.
void cross_block(const Eigen::MatrixXd& X, const Kernel& kernel, const Eigen::VectorXd& radius, const double* points,
                 Eigen::Index count, double* out, double* noise) {
  const Eigen::Index n = X.rows(), q = X.cols();
  MATLAS_CHECK_EQ(radius.size(), n);
  MATLAS_CHECK_GE(count, Eigen::Index{0});
  Eigen::Map<Eigen::MatrixXd> k(out, n, count);
  const double scale = -1.0 / (kernel.lengthscale * kernel.lengthscale);
  auto squared_distance = [&](Eigen::Index i, Eigen::Index j) {
    double d2 = 0;
    for (Eigen::Index d = 0; d < q; ++d) d2 += (X(i, d) - points[j * q + d]) * (X(i, d) - points[j * q + d]);
    return d2;
  };
  std::vector<char> tapered(static_cast<std::size_t>(count), 0);
  for (Eigen::Index j = 0; j < count; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const double d2 = squared_distance(i, j);
      if (d2 < radius[i] * radius[i] || d2 == 0.0) tapered[static_cast<std::size_t>(j)] = 1;
      k(i, j) = d2 * scale;
    }
  }
  exp_in_place(out, static_cast<std::size_t>(n * count));
  for (Eigen::Index j = 0; j < count; ++j) {
    double s = 0;
    if (tapered[static_cast<std::size_t>(j)])
      for (Eigen::Index i = 0; i < n; ++i) {
        const double d2 = squared_distance(i, j);
        if (!(d2 < radius[i] * radius[i]) && d2 != 0.0) continue;
        const double phi = taper_weight(radius[i], std::sqrt(d2));
        k(i, j) += kernel.nugget * phi;
        s += phi * phi;
      }
    if (noise) noise[j] = kernel.nugget * s;
  }
}

}  // namespace

Eigen::VectorXd GpPosterior::cross(const Eigen::Ref<const Eigen::VectorXd>& x, double* noise) const {
  if (x.size() != X_.cols())
    throw Error("GP posterior: point has dimension " + std::to_string(x.size()) + " but the latent space has " +
                std::to_string(X_.cols()));
  const Eigen::VectorXd point = x;
  Eigen::VectorXd kx(X_.rows());
  cross_block(X_, kernel_, taper_radius_, point.data(), 1, kx.data(), noise);
  return kx;
}

Eigen::VectorXd GpPosterior::weights(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  return llt_.solve(cross(x));
}

Eigen::MatrixXd GpPosterior::weights_batch(const Eigen::MatrixXd& points) const {
  if (points.cols() != X_.cols())
    throw Error("GP posterior: points have dimension " + std::to_string(points.cols()) +
                " but the latent space has " + std::to_string(X_.cols()));
  Eigen::MatrixXd k(X_.rows(), points.rows());
  for (Eigen::Index j = 0; j < points.rows(); ++j) k.col(j) = cross(points.row(j).transpose());
  Eigen::MatrixXd w = llt_.solve(k);
  MATLAS_CHECK(w.rows() == X_.rows() && w.cols() == points.rows());
  return w;
}

double GpPosterior::variance(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  double noise = 0;
  const Eigen::VectorXd kx = cross(x, &noise);
  // k^T K^-1 k = |L^-1 k|^2; c(x, x) = 1 plus the tapered nugget meeting itself.
  return std::max(0.0, 1.0 + noise - llt_.matrixL().solve(kx).squaredNorm());
}

GpPosterior::Batch GpPosterior::predict_batch(const Eigen::MatrixXd& points) const {
  if (points.cols() != X_.cols())
    throw Error("GP posterior: points have dimension " + std::to_string(points.cols()) +
                " but the latent space has " + std::to_string(X_.cols()));
  const Eigen::Index n = X_.rows(), m = points.rows(), q = X_.cols();
  Batch b;
  b.weights.resize(n, m);
  advise_huge_pages(b.weights.data(), static_cast<std::size_t>(b.weights.size()) * sizeof(double));
  b.variance.resize(m);
  if (m == 0) return b;
  MATLAS_CHECK_EQ(llt_.matrixLLT().rows(), n);
  // W = K^-1 k(x) as one product with K^-1 (from the Cholesky factor; 41 us at n = 100) in
  // OpenBLAS's dsymm: Eigen's triangular solves of many right-hand sides (compiled for baseline
  // x86-64) ran at a few GFLOP/s. Variance = c(x, x) - k^T K^-1 k = 1 + noise - k . w.
  const Eigen::MatrixXd Kinv = inverse();
  const int nn = static_cast<int>(n);
  const Eigen::MatrixXd P = points.transpose();  // q x m: point j's coordinates contiguous
  // Blocks of columns that keep k(x) in cache, in parallel.
  constexpr Eigen::Index kBlock = 256;
  const Eigen::Index blocks = (m + kBlock - 1) / kBlock;
  parallel_for_each(0, static_cast<std::size_t>(blocks), [&](std::size_t block) {
    const Eigen::Index first = static_cast<Eigen::Index>(block) * kBlock, count = std::min(kBlock, m - first);
    Eigen::MatrixXd k(n, count);
    Eigen::VectorXd noise(count);
    cross_block(X_, kernel_, taper_radius_, P.data() + first * q, count, k.data(), noise.data());
    double* w = b.weights.data() + first * n;
    blas::openblas().dsymm(CblasColMajor, CblasLeft, CblasLower, nn, static_cast<int>(count), 1.0, Kinv.data(), nn,
                           k.data(), nn, 0.0, w, nn);
    for (Eigen::Index j = 0; j < count; ++j) {
      MATLAS_DCHECK(noise[j] >= 0, "the tapered nugget's self-covariance is a sum of squares");
      b.variance[first + j] = std::max(0.0, 1.0 + noise[j] - k.col(j).dot(b.weights.col(first + j)));
    }
  });
  return b;
}

Eigen::MatrixXd GpPosterior::inverse() const {
  Eigen::MatrixXd Kinv = llt_.matrixLLT();
  const auto n = static_cast<int>(Kinv.rows());
  if (blas::inverse_from_cholesky(n, Kinv.data(), n) != 0)
    throw Error("GP posterior: inverting the covariance matrix failed");
  Kinv.triangularView<Eigen::StrictlyUpper>() = Kinv.transpose();
  return Kinv;
}

namespace {

/// The smooth kernel between the data points and the cells of a grid's lines (rows or columns):
/// on line l, k_i(cell j) = d(i, l) F(i, j), with F(i, j) = exp(-s (t_j - a_i)^2) in the line's
/// coordinate t and d(i, l) = exp(-s (perp2_i + (t'_l - b_i)^2)) across it; V: F's first `rank`
/// right singular vectors (those over 1e-15 of the largest singular value).
struct GridLines {
  Eigen::MatrixXd F;  ///< n x cells per line
  Eigen::MatrixXd d;  ///< n x lines
  Eigen::MatrixXd V;  ///< cells per line x rank
  Eigen::Index rank = 0;
};

GridLines grid_lines(const Eigen::VectorXd& along, const Eigen::VectorXd& across, const Eigen::VectorXd& a,
                     const Eigen::VectorXd& b, const Eigen::VectorXd& perp2, double s) {
  const Eigen::Index n = a.size(), m = along.size(), lines = across.size();
  GridLines g;
  g.F.resize(n, m);
  g.d.resize(n, lines);
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = 0; i < n; ++i) g.F(i, j) = std::exp(-s * (along[j] - a[i]) * (along[j] - a[i]));
  for (Eigen::Index l = 0; l < lines; ++l)
    for (Eigen::Index i = 0; i < n; ++i)
      g.d(i, l) = std::exp(-s * (perp2[i] + (across[l] - b[i]) * (across[l] - b[i])));
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(g.F, Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  g.rank = 1;
  while (g.rank < sigma.size() && sigma[g.rank] > 1e-15 * sigma[0]) ++g.rank;
  g.V = svd.matrixV().leftCols(g.rank);
  return g;
}

}  // namespace

GpPosterior::Batch GpPosterior::predict_grid(const PlaneGrid& grid) const {
  const Eigen::Index n = X_.rows(), q = X_.cols(), cols = grid.u.size(), rows = grid.v.size();
  if (grid.origin.size() != q || grid.axis_u.size() != q || grid.axis_v.size() != q)
    throw Error("GP posterior: the grid's plane has dimension " + std::to_string(grid.origin.size()) +
                " but the latent space has " + std::to_string(q));
  if (!grid.origin.allFinite() || !grid.axis_u.allFinite() || !grid.axis_v.allFinite() || !grid.u.allFinite() ||
      !grid.v.allFinite())
    throw Error("GP posterior: the grid's plane or coordinates contain NaN or infinity");
  const Eigen::Index cells = cols * rows;
  auto points = [&] {
    Eigen::MatrixXd P(cells, q);
    for (Eigen::Index r = 0; r < rows; ++r)
      for (Eigen::Index c = 0; c < cols; ++c)
        P.row(r * cols + c) = (grid.origin + grid.u[c] * grid.axis_u + grid.v[r] * grid.axis_v).transpose();
    return P;
  };
  const Eigen::VectorXd &au = grid.axis_u, &av = grid.axis_v;
  const bool orthonormal = std::abs(au.norm() - 1) < 1e-12 && std::abs(av.norm() - 1) < 1e-12 &&
                           std::abs(au.dot(av)) < 1e-12;
  if (cells == 0 || !orthonormal) return predict_batch(points());
  // The data points' plane coordinates and squared distances from the plane: |x_i - cell|^2 =
  // perp2_i + (u - alpha_i)^2 + (v - beta_i)^2.
  Eigen::VectorXd alpha(n), beta(n), perp2(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXd p = X_.row(i).transpose() - grid.origin;
    alpha[i] = au.dot(p);
    beta[i] = av.dot(p);
    perp2[i] = (p - alpha[i] * au - beta[i] * av).squaredNorm();
  }
  const double s = 1.0 / (kernel_.lengthscale * kernel_.lengthscale);
  GridLines by_rows = grid_lines(grid.u, grid.v, alpha, beta, perp2, s);
  GridLines by_cols = grid_lines(grid.v, grid.u, beta, alpha, perp2, s);
  const bool along_u = rows * by_rows.rank <= cols * by_cols.rank;
  const GridLines& g = along_u ? by_rows : by_cols;
  const Eigen::Index lines = along_u ? rows : cols, m = along_u ? cols : rows, R = g.rank;
  if (2 * lines * R > cells) return predict_batch(points());  // little to gain
  const Eigen::VectorXd &t = along_u ? grid.u : grid.v, &t_across = along_u ? grid.v : grid.u;
  const Eigen::VectorXd &a = along_u ? alpha : beta, &b = along_u ? beta : alpha;

  // T = K^-1 [diag(d_l) F V]_l: one product of K^-1 by n x (lines R), in parallel blocks.
  const Eigen::MatrixXd Kinv = inverse();
  const Eigen::MatrixXd FV = g.F * g.V;  // n x R
  Eigen::MatrixXd Y(n, lines * R), T(n, lines * R);
  for (Eigen::Index l = 0; l < lines; ++l) Y.middleCols(l * R, R) = g.d.col(l).asDiagonal() * FV;
  const int nn = static_cast<int>(n);
  constexpr Eigen::Index kBlock = 256;
  const Eigen::Index blocks = (Y.cols() + kBlock - 1) / kBlock;
  parallel_for_each(0, static_cast<std::size_t>(blocks), [&](std::size_t block) {
    const Eigen::Index first = static_cast<Eigen::Index>(block) * kBlock, count = std::min(kBlock, Y.cols() - first);
    blas::openblas().dsymm(CblasColMajor, CblasLeft, CblasLower, nn, static_cast<int>(count), 1.0, Kinv.data(), nn,
                           Y.col(first).data(), nn, 0.0, T.col(first).data(), nn);
  });
  // The nugget's taper: only data points closer to the plane than their radius reach a cell.
  std::vector<Eigen::Index> near_plane;
  for (Eigen::Index i = 0; i < n; ++i)
    if (perp2[i] < taper_radius_[i] * taper_radius_[i] || perp2[i] == 0.0) near_plane.push_back(i);

  Batch out;
  out.weights.resize(n, cells);
  advise_huge_pages(out.weights.data(), static_cast<std::size_t>(out.weights.size()) * sizeof(double));
  out.variance.resize(cells);
  out.rank = R;
  parallel_for_each(0, static_cast<std::size_t>(lines), [&](std::size_t line) {
    const auto l = static_cast<Eigen::Index>(line);
    // The line's weights T_l V^T, written in place where the line's cells are consecutive (a row).
    thread_local Eigen::MatrixXd scratch;
    if (!along_u) scratch.resize(n, m);
    double* w = along_u ? out.weights.col(l * cols).data() : scratch.data();
    blas::openblas().dgemm(CblasColMajor, CblasNoTrans, CblasTrans, nn, static_cast<int>(m), static_cast<int>(R), 1.0,
                           T.col(l * R).data(), nn, g.V.data(), static_cast<int>(m), 0.0, w, nn);
    Eigen::Map<Eigen::MatrixXd> W(w, n, m);
    // The nugget's taper at the cells within a data point's radius: k_i += nugget phi.
    struct Tapered {
      Eigen::Index i, j;
      double phi;
    };
    std::vector<Tapered> tapered;
    for (const Eigen::Index i : near_plane) {
      const double r = taper_radius_[i];
      for (Eigen::Index j = 0; j < m; ++j) {
        const double d2 = perp2[i] + (t[j] - a[i]) * (t[j] - a[i]) + (t_across[l] - b[i]) * (t_across[l] - b[i]);
        if (!(d2 < r * r) && d2 != 0.0) continue;
        tapered.push_back({i, j, taper_weight(r, std::sqrt(d2))});
        W.col(j) += (kernel_.nugget * tapered.back().phi) * Kinv.col(i);
      }
    }
    // Variance = 1 + nugget sum phi^2 - k . w, with the exact kernel values k_i = d_i F_ij.
    const auto d = g.d.col(l).array();
    for (Eigen::Index j = 0; j < m; ++j) {
      double noise = 0, kw = (d * g.F.col(j).array() * W.col(j).array()).sum();
      for (const Tapered& e : tapered)
        if (e.j == j) {
          noise += e.phi * e.phi;
          kw += kernel_.nugget * e.phi * W(e.i, j);
        }
      const Eigen::Index cell = along_u ? l * cols + j : j * cols + l;
      if (!along_u) out.weights.col(cell) = W.col(j);
      out.variance[cell] = std::max(0.0, 1.0 + kernel_.nugget * noise - kw);
    }
  });
  return out;
}

double GpPosterior::log_det() const {
  // The constructor accepted the factor's pivots (all positive), so the logarithm is finite.
  const double value = 2.0 * llt_.matrixLLT().diagonal().array().log().sum();
  MATLAS_CHECK(std::isfinite(value), "log|K| of a positive definite K");
  return value;
}

double GpPosterior::condition_estimate() const {
  const Eigen::Index n = X_.rows();
  // Deterministic, non-symmetric start vector (not orthogonal to the extreme eigenvectors in
  // practice).
  Eigen::VectorXd start(n);
  for (Eigen::Index i = 0; i < n; ++i) start[i] = 1.0 + 0.5 * std::sin(1.0 + 7.0 * static_cast<double>(i));
  start.normalize();
  const Eigen::MatrixXd K = covariance_matrix(X_, kernel_);
  constexpr int kSteps = 50;
  Eigen::VectorXd v = start;
  double lambda_max = 0;
  for (int s = 0; s < kSteps; ++s) {
    const Eigen::VectorXd w = K.selfadjointView<Eigen::Lower>() * v;
    lambda_max = v.dot(w);
    v = w.normalized();
  }
  v = start;
  double inv_lambda_min = 0;  // largest eigenvalue of K^-1
  for (int s = 0; s < kSteps; ++s) {
    const Eigen::VectorXd w = llt_.solve(v);
    inv_lambda_min = v.dot(w);
    v = w.normalized();
  }
  MATLAS_CHECK(lambda_max > 0 && inv_lambda_min > 0, "Rayleigh quotients of a positive definite K");
  return lambda_max * inv_lambda_min;
}

}  // namespace matlas::gp
