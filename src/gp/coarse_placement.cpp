#include "gp/coarse_placement.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include "core/check.h"
#include "core/error.h"

namespace matlas::gp {

std::vector<Eigen::Index> coarse_subset(Eigen::Index n, int count, std::uint64_t seed) {
  if (count < 1) throw Error("coarse placement: the subset needs at least one item (got " + std::to_string(count) + ")");
  std::vector<Eigen::Index> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), Eigen::Index{0});
  if (count >= n) return all;
  // A partial Fisher-Yates shuffle: the first `count` entries are a uniform sample.
  std::mt19937_64 rng(seed);
  for (std::size_t k = 0; k < static_cast<std::size_t>(count); ++k) {
    std::uniform_int_distribution<std::size_t> pick(k, all.size() - 1);
    std::swap(all[k], all[pick(rng)]);
  }
  all.resize(static_cast<std::size_t>(count));
  std::sort(all.begin(), all.end());
  return all;
}

SparseProblem subset_problem(const SparseProblem& p, const std::vector<Eigen::Index>& rows) {
  const Eigen::Index n = p.data.factor.rows();
  SparseProblem s = p;
  s.data.factor.resize(static_cast<Eigen::Index>(rows.size()), p.data.factor.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (rows[k] < 0 || rows[k] >= n) throw Error("coarse placement: a subset row is out of range");
    s.data.factor.row(static_cast<Eigen::Index>(k)) = p.data.factor.row(rows[k]);
  }
  s.data.residual = p.data.residual * static_cast<double>(rows.size()) / static_cast<double>(n);
  return s;
}

namespace {

/// interpolate_layout's work for any source of distances: block_distances(rows of `rest`) gives
/// the squared distances of those items (rows) to the subset's (columns, in the order of `rows`).
Eigen::MatrixXd interpolate_from_distances(
    Eigen::Index n, const std::vector<Eigen::Index>& rows, const Eigen::MatrixXd& placed, int neighbours, double jitter,
    const std::function<Eigen::MatrixXd(const std::vector<Eigen::Index>&)>& block_distances) {
  const Eigen::Index c = static_cast<Eigen::Index>(rows.size()), q = placed.cols();
  if (neighbours < 1) throw Error("coarse placement: need at least one neighbour");
  if (c == 0 || placed.rows() != c || q == 0)
    throw Error("coarse placement: " + std::to_string(placed.rows()) + " placed points for " + std::to_string(c) +
                " subset items");
  if (!placed.allFinite()) throw Error("coarse placement: the subset's layout is not finite");
  std::vector<char> in_subset(static_cast<std::size_t>(n), 0);
  for (const Eigen::Index i : rows) {
    if (i < 0 || i >= n || in_subset[static_cast<std::size_t>(i)] != 0)
      throw Error("coarse placement: subset rows must be distinct and within the data");
    in_subset[static_cast<std::size_t>(i)] = 1;
  }
  std::vector<Eigen::Index> rest;
  for (Eigen::Index i = 0; i < n; ++i)
    if (in_subset[static_cast<std::size_t>(i)] == 0) rest.push_back(i);

  Eigen::MatrixXd X(n, q);
  for (Eigen::Index k = 0; k < c; ++k) X.row(rows[static_cast<std::size_t>(k)]) = placed.row(k);
  const Eigen::RowVectorXd centroid = placed.colwise().mean();
  const double radius = std::sqrt((placed.rowwise() - centroid).squaredNorm() / static_cast<double>(c));
  const int k_near = static_cast<int>(std::min<Eigen::Index>(neighbours, c));
  std::mt19937_64 rng(0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  // Squared distances in blocks of rows (a 1024 x c block at a time), nearest by partial sort.
  constexpr std::size_t kBlock = 1024;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(c));
  for (std::size_t b = 0; b < rest.size(); b += kBlock) {
    const std::vector<Eigen::Index> block(rest.begin() + static_cast<std::ptrdiff_t>(b),
                                          rest.begin() + static_cast<std::ptrdiff_t>(std::min(rest.size(), b + kBlock)));
    const Eigen::MatrixXd D2 = block_distances(block);
    MATLAS_CHECK(D2.rows() == static_cast<Eigen::Index>(block.size()) && D2.cols() == c);
    for (std::size_t k = 0; k < block.size(); ++k) {
      const Eigen::Index row = static_cast<Eigen::Index>(k);
      std::iota(order.begin(), order.end(), Eigen::Index{0});
      std::partial_sort(order.begin(), order.begin() + k_near, order.end(),
                        [&](Eigen::Index u, Eigen::Index v) { return D2(row, u) < D2(row, v); });
      Eigen::RowVectorXd x = placed.row(order[0]);  // a duplicate of a placed item: its point
      if (D2(row, order[0]) > 0) {
        x.setZero();
        double total = 0;
        for (int j = 0; j < k_near; ++j) {
          const Eigen::Index s = order[static_cast<std::size_t>(j)];
          const double w = 1.0 / std::sqrt(D2(row, s));  // > 0: the nearest distance is
          x += w * placed.row(s);
          total += w;
        }
        x /= total;
      }
      for (Eigen::Index a = 0; a < q; ++a) x[a] += jitter * radius * normal(rng);
      X.row(block[k]) = x;
    }
  }
  MATLAS_CHECK(X.allFinite(), "the interpolated layout");
  return X;
}

}  // namespace

Eigen::MatrixXd interpolate_layout(const LowRankGram& data, const std::vector<Eigen::Index>& rows,
                                   const Eigen::MatrixXd& placed, int neighbours, double jitter) {
  const Eigen::MatrixXd& Y = data.factor;
  const Eigen::Index c = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd Ysub(c, Y.cols());
  for (Eigen::Index k = 0; k < c; ++k) {
    const Eigen::Index i = rows[static_cast<std::size_t>(k)];
    if (i < 0 || i >= Y.rows()) throw Error("coarse placement: subset rows must be distinct and within the data");
    Ysub.row(k) = Y.row(i);
  }
  const Eigen::VectorXd sub_norms = Ysub.rowwise().squaredNorm();
  return interpolate_from_distances(Y.rows(), rows, placed, neighbours, jitter, [&](const std::vector<Eigen::Index>& block) {
    Eigen::MatrixXd Yb(static_cast<Eigen::Index>(block.size()), Y.cols());
    for (std::size_t k = 0; k < block.size(); ++k) Yb.row(static_cast<Eigen::Index>(k)) = Y.row(block[k]);
    Eigen::MatrixXd D2 = -2.0 * (Yb * Ysub.transpose());
    D2.colwise() += Yb.rowwise().squaredNorm();
    D2.rowwise() += sub_norms.transpose();
    return D2;
  });
}

Eigen::MatrixXd interpolate_layout(const Eigen::MatrixXd& gram, const std::vector<Eigen::Index>& rows,
                                   const Eigen::MatrixXd& placed, int neighbours, double jitter) {
  if (gram.rows() != gram.cols()) throw Error("coarse placement: the Gram matrix must be square");
  for (const Eigen::Index i : rows)
    if (i < 0 || i >= gram.rows()) throw Error("coarse placement: subset rows must be distinct and within the data");
  return interpolate_from_distances(gram.rows(), rows, placed, neighbours, jitter, [&](const std::vector<Eigen::Index>& block) {
    Eigen::MatrixXd D2(static_cast<Eigen::Index>(block.size()), static_cast<Eigen::Index>(rows.size()));
    for (Eigen::Index s = 0; s < D2.cols(); ++s) {
      const Eigen::Index j = rows[static_cast<std::size_t>(s)];
      for (Eigen::Index k = 0; k < D2.rows(); ++k) {
        const Eigen::Index i = block[static_cast<std::size_t>(k)];
        D2(k, s) = gram(i, i) + gram(j, j) - 2.0 * gram(i, j);
      }
    }
    return D2;
  });
}

LikelihoodProblem subset_problem(const LikelihoodProblem& p, const std::vector<Eigen::Index>& rows) {
  const Eigen::Index n = p.gram.rows();
  for (const Eigen::Index i : rows)
    if (i < 0 || i >= n) throw Error("coarse placement: a subset row is out of range");
  LikelihoodProblem s;
  s.gram = p.gram(rows, rows);
  s.columns = p.columns;
  s.kernel = p.kernel;
  s.prior = p.prior;
  return s;
}

OptimizeOptions refinement_options(const OptimizeOptions& o, double spent) {
  OptimizeOptions refine = o;
  refine.coarse = 0;
  refine.starts = 1;
  if (o.time_limit_seconds > 0) refine.time_limit_seconds = std::max(1e-3, o.time_limit_seconds - spent);
  return refine;
}

OptimizeResult with_coarse_stage(OptimizeResult refined, const OptimizeResult& coarse,
                                 std::chrono::steady_clock::time_point begin) {
  refined.iterations += coarse.iterations;
  refined.evaluations += coarse.evaluations;
  refined.best_start = coarse.best_start;
  refined.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return refined;
}

}  // namespace matlas::gp
