#include "gp/convex_weights.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "core/blas.h"
#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "core/parallel.h"

namespace matlas::gp {

ConvexProjection::ConvexProjection(const Eigen::MatrixXd& gram, double ridge) : ridge_(ridge) {
  if (gram.rows() != gram.cols() || gram.rows() == 0)
    throw Error("convex weights: the Gram matrix must be square and non-empty");
  if (!gram.allFinite()) throw Error("convex weights: the Gram matrix contains NaN or infinity");
  if (!(ridge > 0) || !std::isfinite(ridge))
    throw Error("convex weights: the ridge must be finite and > 0, got " + std::to_string(ridge));
  const double n = static_cast<double>(gram.rows());
  const double trace = gram.trace();
  // All inputs identical (S = 0): the metric is the ridge alone, i.e. the Euclidean projection.
  const double scale = trace > 0 ? trace / n : 1.0;
  A_ = 0.5 * (gram + gram.transpose()) / scale;
  A_.diagonal().array() += ridge;
}

Eigen::VectorXd ConvexProjection::from_centred(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  return project(Combination(w).affine());
}

// The iterate of the active-set method and the Cholesky factor of A_FF on its free set F, kept
// up to date as F changes by one index at a time (O(|F|^2) instead of a factorisation, O(|F|^3),
// per change) and from one point to the next: neighbouring points mostly end on the same F.
// The forward solutions y_b = L^-1 b_F and y_1 = L^-1 1 are kept up to date with the factor too
// (O(|F|) per change: a new row's entry, or the removal's rotations applied to them), so that the
// free set's optimum costs one backward solve: c_F = L^-T (y_b + nu y_1), with sum c_F =
// y_1 . (y_b + nu y_1) = 1 fixing nu.
struct ConvexProjection::Iterate {
  Eigen::VectorXd c;                // feasible: c >= 0, sum c = 1; empty: no start yet
  std::vector<Eigen::Index> order;  // F, in the factor's order
  std::vector<Eigen::Index> pos;    // position in `order` of each index, -1 where bound
  std::vector<double> L;            // A_FF = L L^T, row-major lower triangle, row stride n
  std::vector<double> yb, y1, cF, x;  // L^-1 b_F, L^-1 1, the free set's optimum, scratch
  std::vector<std::pair<double, Eigen::Index>> negative;  // bound coefficients to free: (multiplier, index)
  bool yb_valid = false, y1_valid = false;  // yb: for the b of this solve (it.b)
  Eigen::VectorXd b, r;

  bool free(Eigen::Index i) const { return pos[static_cast<std::size_t>(i)] >= 0; }
  std::size_t size() const { return order.size(); }
  double& l(std::size_t i, std::size_t k) { return L[i * static_cast<std::size_t>(c.size()) + k]; }

  /// The cold start: g clipped at 0 and renormalised (its positive parts sum to at least 1), F its
  /// support.
  void start_from(const Eigen::MatrixXd& A, const Eigen::Ref<const Eigen::VectorXd>& g) {
    const Eigen::Index n = g.size();
    c = g.cwiseMax(0.0);
    MATLAS_DCHECK(c.sum() > 0, "coefficients summing to 1 have a positive part");
    c /= c.sum();
    order.clear();
    yb_valid = y1_valid = false;
    pos.assign(static_cast<std::size_t>(n), -1);
    L.resize(static_cast<std::size_t>(n * n));
    for (Eigen::Index i = 0; i < n; ++i)
      if (c[i] > 0) add(A, i);
  }

  /// Row i of the factor, its first `count` entries (contiguous: L is stored by rows).
  Eigen::Map<const Eigen::VectorXd> row(std::size_t i, std::size_t count) const {
    return {L.data() + i * static_cast<std::size_t>(c.size()), static_cast<Eigen::Index>(count)};
  }

  /// y = L^-1 rhs (rhs and y may be the same array): a dot product with each row (Eigen's
  /// vectorised reduction).
  void forward(const double* rhs, double* y) {
    for (std::size_t i = 0; i < size(); ++i) {
      const Eigen::Map<const Eigen::VectorXd> done(y, static_cast<Eigen::Index>(i));
      y[i] = (rhs[i] - row(i, i).dot(done)) / l(i, i);
    }
  }
  /// y = L^-T y, in place: column i of L^T is row i of L, so each solved y_i is subtracted from
  /// the ones before it along that row (contiguous, vectorised), instead of a strided column walk.
  void backward(double* y) {
    for (std::size_t i = size(); i-- > 0;) {
      y[i] /= l(i, i);
      Eigen::Map<Eigen::VectorXd>(y, static_cast<Eigen::Index>(i)) -= y[i] * row(i, i);
    }
  }

  /// F += {j}: a row appended to the factor.
  void add(const Eigen::MatrixXd& A, Eigen::Index j) {
    const std::size_t m = size();
    x.resize(m + 1);
    for (std::size_t k = 0; k < m; ++k) x[k] = A(order[k], j);
    forward(x.data(), x.data());
    double d = A(j, j);
    for (std::size_t k = 0; k < m; ++k) d -= x[k] * x[k], l(m, k) = x[k];
    // A_FF is a principal submatrix of a positive definite A: d >= its smallest eigenvalue > 0.
    if (!(d > 0)) throw Error("convex weights: the metric is not positive definite (ridge too small)");
    l(m, m) = std::sqrt(d);
    // The forward solutions gain the new row's entry.
    const Eigen::Map<const Eigen::VectorXd> row_m(x.data(), static_cast<Eigen::Index>(m));
    if (y1_valid) y1.push_back((1.0 - row_m.dot(Eigen::Map<const Eigen::VectorXd>(y1.data(), row_m.size()))) / l(m, m));
    if (yb_valid)
      yb.push_back((b[j] - row_m.dot(Eigen::Map<const Eigen::VectorXd>(yb.data(), row_m.size()))) / l(m, m));
    order.push_back(j);
    pos[static_cast<std::size_t>(j)] = static_cast<Eigen::Index>(m);
  }

  /// F -= {j}: its row and column leave the factor, and the rows below it take a rank-1 update
  /// (their part of the removed column folded back in: L22' L22'^T = L22 L22^T + x x^T) by
  /// Givens rotations of the columns (k, removed); the same rotations of the unknowns turn the
  /// forward solutions into those of the new factor (the equations of the rows kept still hold).
  void remove(Eigen::Index j) {
    const auto p = static_cast<std::size_t>(pos[static_cast<std::size_t>(j)]);
    const std::size_t m = size();
    x.resize(m);
    for (std::size_t i = p + 1; i < m; ++i) {
      x[i - p - 1] = l(i, p);
      for (std::size_t k = 0; k < p; ++k) l(i - 1, k) = l(i, k);
      for (std::size_t k = p + 1; k <= i; ++k) l(i - 1, k - 1) = l(i, k);
    }
    const std::size_t len = m - 1 - p;
    double removed_b = 0, removed_1 = 0;  // the removed row's unknowns, rotated along
    if (yb_valid) removed_b = yb[p], yb.erase(yb.begin() + static_cast<std::ptrdiff_t>(p));
    if (y1_valid) removed_1 = y1[p], y1.erase(y1.begin() + static_cast<std::ptrdiff_t>(p));
    for (std::size_t k = 0; k < len; ++k) {
      const double lkk = l(p + k, p + k);
      const double norm = std::hypot(lkk, x[k]);
      const double cs = norm / lkk, sn = x[k] / lkk;
      l(p + k, p + k) = norm;
      for (std::size_t i = k + 1; i < len; ++i) {
        l(p + i, p + k) = (l(p + i, p + k) + sn * x[i]) / cs;
        x[i] = cs * x[i] - sn * l(p + i, p + k);
      }
      // The rotation (cos, sin) = (lkk, x_k) / norm of the unknowns (y_k, removed).
      const double co = lkk / norm, si = x[k] / norm;
      if (yb_valid) rotate(yb[p + k], removed_b, co, si);
      if (y1_valid) rotate(y1[p + k], removed_1, co, si);
    }
    order.erase(order.begin() + static_cast<std::ptrdiff_t>(p));
    pos[static_cast<std::size_t>(j)] = -1;
    for (std::size_t i = p; i < order.size(); ++i)
      pos[static_cast<std::size_t>(order[i])] = static_cast<Eigen::Index>(i);
  }

  static void rotate(double& kept, double& removed, double co, double si) {
    const double k = kept;
    kept = co * k + si * removed;
    removed = co * removed - si * k;
  }
};

ConvexProjection::WarmStart::WarmStart() : it_(std::make_unique<Iterate>()) {}
ConvexProjection::WarmStart::~WarmStart() = default;
ConvexProjection::WarmStart::WarmStart(WarmStart&&) noexcept = default;
ConvexProjection::WarmStart& ConvexProjection::WarmStart::operator=(WarmStart&&) noexcept = default;

Eigen::VectorXd ConvexProjection::from_centred(const Eigen::Ref<const Eigen::VectorXd>& w, WarmStart& warm) const {
  Eigen::VectorXd g = Combination(w).affine();
  const bool convex = g.minCoeff() >= 0;
  project_from(g, *warm.it_);
  if (!convex) settle(g, warm.it_->b);
  return g;
}

double ConvexProjection::check(const Eigen::Ref<const Eigen::VectorXd>& g) const {
  const Eigen::Index n = A_.rows();
  if (g.size() != n)
    throw Error("convex weights: " + std::to_string(g.size()) + " coefficients for " + std::to_string(n) + " inputs");
  if (!g.allFinite()) throw Error("convex weights: coefficients contain NaN or infinity");
  const double total = g.sum();
  if (std::abs(total - 1.0) > 1e-8 * std::max(1.0, g.lpNorm<1>()))
    throw Error("convex weights: coefficients sum to " + std::to_string(total) + ", not 1");
  return total;
}

Eigen::VectorXd ConvexProjection::project(const Eigen::Ref<const Eigen::VectorXd>& g) const {
  Eigen::VectorXd c = g;
  Iterate it;
  project_from(c, it);
  if (it.c.size() == c.size()) settle(c, it.b);
  return c;
}

void ConvexProjection::settle(Eigen::Ref<Eigen::VectorXd> c, const Eigen::VectorXd& b) const {
  // The optimum's support in increasing order, and the free-set optimum on it from a fresh
  // factorisation: A_SS c_S = b_S + nu 1, sum c_S = 1.
  std::vector<Eigen::Index> support;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    if (c[i] > 0) support.push_back(i);
  const auto m = static_cast<Eigen::Index>(support.size());
  Eigen::MatrixXd rhs(m, 2);
  rhs.col(0) = b(support);
  rhs.col(1).setOnes();
  const Eigen::LLT<Eigen::MatrixXd> llt(A_(support, support));
  if (llt.info() != Eigen::Success) return;  // keep the active-set method's own c
  const Eigen::MatrixXd uv = llt.solve(rhs);
  const double nu = (1.0 - uv.col(0).sum()) / uv.col(1).sum();
  const Eigen::VectorXd cS = uv.col(0) + nu * uv.col(1);
  // Rounding only: the support's optimum is positive where the method left it positive.
  if (!cS.allFinite() || cS.minCoeff() < -1e-9) return;
  c.setZero();
  c(support) = cS.cwiseMax(0.0);
  c /= c.sum();
}

void ConvexProjection::project_from(Eigen::Ref<Eigen::VectorXd> g, Iterate& it, const double* b) const {
  const double total = check(g);
  if (g.minCoeff() >= 0) {  // already convex: the GP's own answer
    g /= total;
    return;
  }
  if (it.c.size() != g.size()) it.start_from(A_, g);
  if (b)
    it.b = Eigen::Map<const Eigen::VectorXd>(b, g.size());
  else
    it.b.noalias() = A_ * g;
  it.yb_valid = false;  // a new b
  solve(it.b, it);
  MATLAS_DCHECK(it.c.size() == g.size() && it.c.minCoeff() >= 0, "the active-set iterate stays feasible");
  g = it.c;
}

double ConvexProjection::free_set_optimum(const Eigen::VectorXd& b, Iterate& it) const {
  // A_FF c_F = b_F + nu 1, sum c_F = 1: c_F = L^-T (y_b + nu y_1), and 1^T L^-T = y_1^T gives
  // sum c_F = y_1 . y_b + nu y_1 . y_1.
  const std::size_t m = it.size();
  if (!it.y1_valid) {
    it.y1.assign(m, 1.0);
    it.forward(it.y1.data(), it.y1.data());
    it.y1_valid = true;
  }
  if (!it.yb_valid) {
    it.yb.resize(m);
    for (std::size_t s = 0; s < m; ++s) it.yb[s] = b[it.order[s]];
    it.forward(it.yb.data(), it.yb.data());
    it.yb_valid = true;
  }
  const auto em = static_cast<Eigen::Index>(m);
  const Eigen::Map<const Eigen::VectorXd> yb(it.yb.data(), em), y1(it.y1.data(), em);
  const double nu = (1.0 - y1.dot(yb)) / y1.squaredNorm();
  it.cF.resize(m);
  Eigen::Map<Eigen::VectorXd>(it.cF.data(), em) = yb + nu * y1;
  it.backward(it.cF.data());
  return nu;
}

void ConvexProjection::negative_multipliers(const Eigen::VectorXd& b, double nu, double tolerance, Iterate& it) const {
  const Eigen::Index n = A_.rows();
  const std::size_t m = it.size();
  // (A c)_j of the bound j: the free columns summed (vectorised) while F is the smaller part,
  // else one dot product over F per bound j.
  const bool by_columns = 2 * m <= static_cast<std::size_t>(n);
  if (by_columns) {
    it.r.setZero(n);
    for (std::size_t s = 0; s < m; ++s) it.r.noalias() += it.cF[s] * A_.col(it.order[s]);
  }
  it.negative.clear();
  for (Eigen::Index j = 0; j < n; ++j) {
    if (it.free(j)) continue;
    double Ac = 0;
    if (by_columns)
      Ac = it.r[j];
    else
      for (std::size_t s = 0; s < m; ++s) Ac += A_(it.order[s], j) * it.cF[s];
    const double lambda = Ac - b[j] - nu;
    if (lambda < -tolerance) it.negative.emplace_back(lambda, j);
  }
  // The most negative first (ties by index: the order does not depend on anything else).
  const std::size_t keep = std::min(it.negative.size(), kFreedAtOnce);
  std::partial_sort(it.negative.begin(), it.negative.begin() + static_cast<std::ptrdiff_t>(keep), it.negative.end());
  it.negative.resize(keep);
}

void ConvexProjection::solve(const Eigen::VectorXd& b, Iterate& it) const {
  const Eigen::Index n = A_.rows();
  Eigen::VectorXd& c = it.c;
  const double tolerance = 1e-11 * (1.0 + b.cwiseAbs().maxCoeff());
  const int max_iterations = 10 * static_cast<int>(n) + 10;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    const double nu = free_set_optimum(b, it);
    const std::size_t m = it.size();
    if (it.cF.empty() || *std::min_element(it.cF.begin(), it.cF.end()) >= 0) {
      // At the optimum of the free set: optimal if every bound's multiplier is >= 0; otherwise
      // free the most negative one.
      c.setZero();
      for (std::size_t s = 0; s < m; ++s) c[it.order[s]] = it.cF[s];
      negative_multipliers(b, nu, tolerance, it);
      if (it.negative.empty()) {
        c /= c.sum();
        return;
      }
      for (const auto& [lambda, j] : it.negative) it.add(A_, j);
      continue;
    }
    // Step from c towards c_F until the first free coefficient reaches 0; that one becomes bound.
    double alpha = 1.0;
    Eigen::Index blocking = -1;
    for (std::size_t s = 0; s < m; ++s) {
      const Eigen::Index k = it.order[s];
      if (it.cF[s] < 0) {
        const double a = c[k] / (c[k] - it.cF[s]);
        if (a < alpha) {
          alpha = a;
          blocking = k;
        }
      }
    }
    for (std::size_t s = 0; s < m; ++s) {
      const Eigen::Index k = it.order[s];
      c[k] = std::max(0.0, c[k] + alpha * (it.cF[s] - c[k]));
    }
    if (blocking >= 0) {
      c[blocking] = 0;
      it.remove(blocking);
    }
    // Free coefficients at 0 stay free (c_i > 0 only where free holds either way).
  }
  // Not reached for a positive definite A (the active-set method terminates); should rounding make
  // it cycle, c is still a feasible convex combination, only not exactly the closest one.
  c /= c.sum();
}

void ConvexProjection::project_batch(Eigen::Ref<Eigen::MatrixXd> G, Eigen::Index run) const {
  const Eigen::Index m = G.cols();
  if (m == 0) return;
  if (G.rows() != A_.rows())
    throw Error("convex weights: " + std::to_string(G.rows()) + " coefficients for " + std::to_string(A_.rows()) +
                " inputs");
  if (run <= 0 || run > m) run = m;
  const Eigen::Index runs = (m + run - 1) / run;
  MATLAS_CHECK(runs >= 1 && (runs - 1) * run < m, "every run starts at a column");
  // The runs' first columns in turn, each from the one before; their iterates start the runs.
  std::vector<Iterate> starts(static_cast<std::size_t>(runs));
  Iterate it;
  for (Eigen::Index r = 0; r < runs; ++r) {
    project_from(G.col(r * run), it);
    starts[static_cast<std::size_t>(r)] = it;
  }
  // Then the runs in parallel; b = A g of a block of columns at a time by one product.
  constexpr Eigen::Index kBlock = 128;
  const int nn = static_cast<int>(A_.rows());
  parallel_for_each(0, static_cast<std::size_t>(runs), [&](std::size_t r) {
    Iterate& own = starts[r];
    const Eigen::Index first = static_cast<Eigen::Index>(r) * run + 1;
    const Eigen::Index end = std::min(m, first - 1 + run);
    Eigen::MatrixXd B(A_.rows(), kBlock);
    for (Eigen::Index j0 = first; j0 < end; j0 += kBlock) {
      const Eigen::Index count = std::min(kBlock, end - j0);
      blas::openblas().dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nn, static_cast<int>(count), nn, 1.0,
                             A_.data(), nn, G.col(j0).data(), static_cast<int>(G.outerStride()), 0.0, B.data(), nn);
      for (Eigen::Index j = j0; j < j0 + count; ++j) project_from(G.col(j), own, B.col(j - j0).data());
    }
  });
}

void ConvexProjection::from_centred_batch(Eigen::Ref<Eigen::MatrixXd> W, Eigen::Index run) const {
  const double n = static_cast<double>(W.rows());
  for (Eigen::Index j = 0; j < W.cols(); ++j) W.col(j).array() += Combination::mean_weight(W.col(j)) / n;
  project_batch(W, run);
}

}  // namespace matlas::gp
