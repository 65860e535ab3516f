#include "eval/combination_pass.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <tuple>

#include "core/blas.h"
#include "core/error.h"
#include "core/parallel.h"
#include "manifold/column_blocks.h"

namespace matlas::eval {

namespace {
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
}  // namespace

CombinationResult evaluate_combinations(const MaterialSet& set, const CombinationQuery& query,
                                        ProgressSink& progress) {
  const auto n = static_cast<Eigen::Index>(set.size());
  const Eigen::Index m = query.coefficients.rows();
  if (query.coefficients.cols() != n)
    throw Error("combination pass: " + std::to_string(query.coefficients.cols()) +
                " coefficients per item for " + std::to_string(n) + " materials");
  for (const auto& [a, b] : query.pairs)
    if (a < 0 || b < 0 || a >= m || b >= m) throw Error("combination pass: pair index out of range");
  if (query.value_stride < 1) throw Error("combination pass: value stride must be >= 1");

  const std::vector<double> cosine = bin_cosine_factors(set.dims());
  const std::size_t bins = set.dims().bins();
  const std::size_t stride = static_cast<std::size_t>(query.value_stride);

  std::vector<DistanceSums> sums(query.pairs.size());
  std::vector<std::size_t> negatives(static_cast<std::size_t>(m), 0);
  std::size_t values = 0;
  // The pairs summed through the first k items' Grams (lower triangles, column-major), the others
  // by differences.
  const int k = static_cast<int>(std::clamp<Eigen::Index>(query.gram_items, 0, m));
  std::vector<std::size_t> by_difference;
  for (std::size_t p = 0; p < query.pairs.size(); ++p) {
    const auto [a, b] = query.pairs[p];
    if (!(a < k && b < k && a != b)) by_difference.push_back(p);
  }
  Eigen::MatrixXd gram_cbrt = Eigen::MatrixXd::Zero(k, k), gram_linear = Eigen::MatrixXd::Zero(k, k);

  BlockOptions options;
  options.label = "evaluating " + std::to_string(m) + " combinations";
  std::tie(options.first_value, options.end_value) = share_of(set.value_count(), query.share.part, query.share.parts);
  options.block_columns = std::clamp<std::size_t>(
      query.memory_budget / (2 * sizeof(double) * static_cast<std::size_t>(std::max<Eigen::Index>(m, 1))),
      1024, 32768);

  Eigen::MatrixXd selected;         // n x J kept values of the block
  std::vector<double> factor;       // J cosine factors
  RowMatrix linear, cube_root;      // m x J: c_b * item value, cbrt of it
  for_each_column_block(
      set,
      [&](const ColumnBlock& block) {
        // Columns used: kept, above the horizon, on the stride.
        std::vector<std::size_t> cols;
        cols.reserve(block.count);
        for (std::size_t j = 0; j < block.count; ++j) {
          const std::size_t v = block.first + j;
          if (block.kept[j] && cosine[v % bins] > 0 && v % stride == 0) cols.push_back(j);
        }
        if (cols.empty()) return;
        const auto J = static_cast<Eigen::Index>(cols.size());
        values += cols.size();
        selected.resize(n, J);
        factor.resize(cols.size());
        for (Eigen::Index c = 0; c < J; ++c) {
          const std::size_t j = cols[static_cast<std::size_t>(c)];
          selected.col(c) = block.values.col(static_cast<Eigen::Index>(j));
          factor[static_cast<std::size_t>(c)] = cosine[(block.first + j) % bins];
        }
        linear.resize(m, J);
        cube_root.resize(m, J);
        parallel_for(0, static_cast<std::size_t>(m), [&](std::size_t lo, std::size_t hi) {
          const auto l = static_cast<Eigen::Index>(lo), len = static_cast<Eigen::Index>(hi - lo);
          linear.middleRows(l, len).noalias() = query.coefficients.middleRows(l, len) * selected;
          for (Eigen::Index r = l; r < l + len; ++r) {
            double* lin = linear.row(r).data();
            double* cbr = cube_root.row(r).data();
            std::size_t neg = 0;
            for (Eigen::Index c = 0; c < J; ++c) {
              neg += lin[c] < 0.0;
              lin[c] *= factor[static_cast<std::size_t>(c)];
              cbr[c] = std::cbrt(lin[c]);
            }
            negatives[static_cast<std::size_t>(r)] += neg;
          }
        });
        if (k > 0) {
          // Row-major k x J rows are a column-major J x k matrix: G += A^T A with A = that.
          const auto& blas = blas::openblas();
          blas.dsyrk(CblasColMajor, CblasLower, CblasTrans, k, static_cast<int>(J), 1.0, cube_root.data(),
                     static_cast<int>(J), 1.0, gram_cbrt.data(), k);
          blas.dsyrk(CblasColMajor, CblasLower, CblasTrans, k, static_cast<int>(J), 1.0, linear.data(),
                     static_cast<int>(J), 1.0, gram_linear.data(), k);
        }
        parallel_for(0, by_difference.size(), [&](std::size_t lo, std::size_t hi) {
          for (std::size_t d = lo; d < hi; ++d) {
            const std::size_t p = by_difference[d];
            const auto [a, b] = query.pairs[p];
            sums[p].cbrt_squared += (cube_root.row(a) - cube_root.row(b)).squaredNorm();
            sums[p].cosine_squared += (linear.row(a) - linear.row(b)).squaredNorm();
            sums[p].values += cols.size();
          }
        }, 16);
      },
      options, progress);

  // |a|^2 + |b|^2 - 2 a.b, 0 below the Gram's resolution: the products' rounding (about 1e-16
  // times the norms times the square root of the values summed) makes smaller sums noise, of
  // either sign, and two identical tables must be at distance 0 whatever the BLAS kernel.
  constexpr double kGramResolution = 1e-12;
  const auto by_gram = [&](const Eigen::MatrixXd& g, Eigen::Index a, Eigen::Index b) {
    const double norms = g(a, a) + g(b, b), d2 = norms - 2.0 * g(std::max(a, b), std::min(a, b));
    return d2 <= kGramResolution * norms ? 0.0 : d2;
  };
  if (k > 0)
    for (std::size_t p = 0; p < query.pairs.size(); ++p) {
      const auto [a, b] = query.pairs[p];
      if (!(a < k && b < k && a != b)) continue;
      sums[p].cbrt_squared = by_gram(gram_cbrt, a, b);
      sums[p].cosine_squared = by_gram(gram_linear, a, b);
      sums[p].values = values;
    }

  CombinationResult result;
  result.values = values;
  result.negatives = std::move(negatives);
  result.distances.reserve(sums.size());
  for (const auto& s : sums) result.distances.push_back(s.finish());
  result.sums = std::move(sums);
  return result;
}

void reduce_combinations(CombinationResult& result, Communicator& comm) {
  if (comm.size() == 1) return;
  // One array: per pair its two sums and count, per item its negatives, then the values.
  std::vector<double> all;
  all.reserve(3 * result.sums.size() + result.negatives.size() + 1);
  for (const DistanceSums& s : result.sums) {
    all.push_back(s.cbrt_squared);
    all.push_back(s.cosine_squared);
    all.push_back(static_cast<double>(s.values));
  }
  for (const std::size_t k : result.negatives) all.push_back(static_cast<double>(k));
  all.push_back(static_cast<double>(result.values));
  comm.sum(all);
  std::size_t at = 0;
  for (DistanceSums& s : result.sums) {
    s.cbrt_squared = all[at++];
    s.cosine_squared = all[at++];
    s.values = static_cast<std::size_t>(all[at++]);
  }
  for (std::size_t& k : result.negatives) k = static_cast<std::size_t>(all[at++]);
  result.values = static_cast<std::size_t>(all[at]);
  for (std::size_t p = 0; p < result.sums.size(); ++p) result.distances[p] = result.sums[p].finish();
}

}  // namespace matlas::eval
