#include "gp/convex_weights.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"

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

Eigen::VectorXd affine_coefficients(const Eigen::Ref<const Eigen::VectorXd>& w) {
  const double n = static_cast<double>(w.size());
  return w.array() + (1.0 - w.sum()) / n;
}

Eigen::VectorXd ConvexProjection::from_centred(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  return project(affine_coefficients(w));
}

Eigen::VectorXd ConvexProjection::project(const Eigen::Ref<const Eigen::VectorXd>& g) const {
  const Eigen::Index n = A_.rows();
  if (g.size() != n)
    throw Error("convex weights: " + std::to_string(g.size()) + " coefficients for " + std::to_string(n) + " inputs");
  if (!g.allFinite()) throw Error("convex weights: coefficients contain NaN or infinity");
  const double total = g.sum();
  if (std::abs(total - 1.0) > 1e-8 * std::max(1.0, g.lpNorm<1>()))
    throw Error("convex weights: coefficients sum to " + std::to_string(total) + ", not 1");
  if (g.minCoeff() >= 0) return g / total;  // already convex: the GP's own answer

  // Feasible start: g clipped at 0 and renormalised (its positive parts sum to at least 1).
  Eigen::VectorXd c = g.cwiseMax(0.0);
  c /= c.sum();
  std::vector<bool> free(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) free[static_cast<std::size_t>(i)] = c[i] > 0;
  const Eigen::VectorXd b = A_ * g;
  const double tolerance = 1e-11 * (1.0 + b.cwiseAbs().maxCoeff());

  std::vector<Eigen::Index> idx;
  Eigen::MatrixXd AFF;
  Eigen::VectorXd bF, cF;
  Eigen::LLT<Eigen::MatrixXd> llt;
  const int max_iterations = 10 * static_cast<int>(n) + 10;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    idx.clear();
    for (Eigen::Index i = 0; i < n; ++i)
      if (free[static_cast<std::size_t>(i)]) idx.push_back(i);
    const auto m = static_cast<Eigen::Index>(idx.size());
    // Equality-constrained problem on the free set: A_FF c_F = b_F + nu 1, sum c_F = 1.
    AFF.resize(m, m);
    bF.resize(m);
    for (Eigen::Index r = 0; r < m; ++r) {
      bF[r] = b[idx[static_cast<std::size_t>(r)]];
      for (Eigen::Index s = 0; s < m; ++s) AFF(r, s) = A_(idx[static_cast<std::size_t>(r)], idx[static_cast<std::size_t>(s)]);
    }
    llt.compute(AFF);
    const Eigen::VectorXd u = llt.solve(bF);
    const Eigen::VectorXd v = llt.solve(Eigen::VectorXd::Ones(m));
    const double nu = (1.0 - u.sum()) / v.sum();
    cF = u + nu * v;

    if (cF.minCoeff() >= 0) {
      // At the optimum of the free set: optimal if every bound's multiplier
      // lambda_j = (A c - b)_j - nu is >= 0; otherwise free the most negative one.
      c.setZero();
      for (Eigen::Index r = 0; r < m; ++r) c[idx[static_cast<std::size_t>(r)]] = cF[r];
      Eigen::Index worst = -1;
      double most_negative = -tolerance;
      for (Eigen::Index j = 0; j < n; ++j) {
        if (free[static_cast<std::size_t>(j)]) continue;
        const double lambda = A_.col(j).dot(c) - b[j] - nu;
        if (lambda < most_negative) {
          most_negative = lambda;
          worst = j;
        }
      }
      if (worst < 0) return c / c.sum();
      free[static_cast<std::size_t>(worst)] = true;
      continue;
    }
    // Step from c towards c_F until the first free coefficient reaches 0; that one becomes bound.
    double alpha = 1.0;
    Eigen::Index blocking = -1;
    for (Eigen::Index r = 0; r < m; ++r) {
      const Eigen::Index k = idx[static_cast<std::size_t>(r)];
      if (cF[r] < 0) {
        const double a = c[k] / (c[k] - cF[r]);
        if (a < alpha) {
          alpha = a;
          blocking = k;
        }
      }
    }
    for (Eigen::Index r = 0; r < m; ++r) {
      const Eigen::Index k = idx[static_cast<std::size_t>(r)];
      c[k] += alpha * (cF[r] - c[k]);
    }
    if (blocking >= 0) {
      c[blocking] = 0;
      free[static_cast<std::size_t>(blocking)] = false;
    }
    c = c.cwiseMax(0.0);
  }
  // Not reached for a positive definite A (the active-set method terminates); should rounding make
  // it cycle, c is still a feasible convex combination, only not exactly the closest one.
  return c / c.sum();
}

}  // namespace matlas::gp
