#include "gp/sparse_repulsion.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/simd_clones.h"
#include "core/vector_math.h"
#include "gp/likelihood.h"

namespace matlas::gp {

namespace {

/// d2[k] = |p_a - p_{a+1+k}|^2 for the `count` points after a in a column-major n x q array of
/// points sorted by their first coordinate (vectorised over the candidates).
MATLAS_SIMD_CLONES void squared_distances_after(const double* points, std::size_t n, std::size_t q, std::size_t a,
                                                std::size_t count, double* d2) {
  for (std::size_t k = 0; k < count; ++k) d2[k] = 0.0;
  for (std::size_t d = 0; d < q; ++d) {
    const double* column = points + d * n;
    const double xa = column[a];
    const double* after = column + a + 1;
    for (std::size_t k = 0; k < count; ++k) {
      const double diff = after[k] - xa;
      d2[k] += diff * diff;
    }
  }
}

/// The repulsion over the pairs (a, b > a) of one range of sorted points: their sum, and their
/// gradient added to `gradient` (n x q, sorted order) unless null.
struct RepulsionChunk {
  const double* points;  // n x q, column-major, sorted by the first coordinate
  std::size_t n, q;
  double inv_r2, cutoff, slab, scale;

  /// The last point (exclusive) within the slab of a point in [begin, end): the rows whose
  /// gradient run() touches are [begin, reach(end)).
  std::size_t reach(std::size_t end) const {
    if (end == 0) return 0;
    std::size_t last = end;
    while (last < n && points[last] - points[end - 1] <= slab) ++last;
    return last;
  }

  /// The sum over the pairs (a, b > a), a in [begin, end); their gradient is added to
  /// `gradient` (rows begin .. reach(end) - 1 of the sorted points, q columns of `rows`
  /// entries each) unless null.
  double run(std::size_t begin, std::size_t end, double* gradient, std::size_t rows) const {
    // Pairs within the cutoff are gathered in batches, so that expm1 and log run as libmvec's
    // vector functions over each batch (one scalar call per pair took 3/4 of an evaluation at
    // n = 10,000). Small batches: the buffers stay in cache and off the page allocator.
    constexpr std::size_t kBatch = 2048;
    std::vector<std::uint32_t> first(kBatch), second(kBatch);
    std::vector<double> e(kBatch), logs(kBatch), d2;
    std::size_t count = 0, last = begin;  // points a + 1 .. last - 1 lie within the slab
    double sum = 0.0;
    const auto flush = [&] {
      expm1_in_place(e.data(), count);  // e^{-u} - 1
      for (std::size_t k = 0; k < count; ++k) logs[k] = kRepulsionFloor - e[k];
      log_in_place(logs.data(), count);
      for (std::size_t k = 0; k < count; ++k) sum += logs[k];
      if (gradient != nullptr) {
        for (std::size_t k = 0; k < count; ++k) {
          const double f = scale * (1.0 + e[k]) / (kRepulsionFloor - e[k]);
          const std::size_t i = first[k], j = second[k];
          for (std::size_t d = 0; d < q; ++d) {
            const double step = f * (points[d * n + i] - points[d * n + j]);
            gradient[d * rows + i - begin] += step;
            gradient[d * rows + j - begin] -= step;
          }
        }
      }
      count = 0;
    };
    for (std::size_t a = begin; a < end; ++a) {
      last = std::max(last, a + 1);
      while (last < n && points[last] - points[a] <= slab) ++last;
      const std::size_t candidates = last - a - 1;
      if (candidates == 0) continue;
      if (count + candidates > first.size()) flush();
      if (candidates > first.size()) {  // more neighbours in the slab than a batch holds: grow it
        first.resize(candidates), second.resize(candidates), e.resize(candidates), logs.resize(candidates);
      }
      d2.resize(std::max(d2.size(), candidates));
      squared_distances_after(points, n, q, a, candidates, d2.data());
      // Every candidate is written and the count advances past the ones within the cutoff (a
      // third here): no branch to mispredict.
      for (std::size_t k = 0; k < candidates; ++k) {
        first[count] = static_cast<std::uint32_t>(a);
        second[count] = static_cast<std::uint32_t>(a + 1 + k);
        e[count] = -d2[k] * inv_r2;
        count += d2[k] < cutoff ? 1 : 0;
      }
    }
    flush();
    return sum;
  }
};

}  // namespace

double sparse_repulsion(const Eigen::MatrixXd& X, double repulsion, double radius, Eigen::MatrixXd* gradient) {
  if (repulsion == 0) return 0.0;
  const Eigen::Index n = X.rows(), q = X.cols();
  MATLAS_CHECK(n < (Eigen::Index{1} << 32), "repulsion pairs index points by 32 bits");
  const double inv_r2 = 1.0 / (radius * radius), cutoff = 40.0 / inv_r2;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return X(a, 0) < X(b, 0); });
  Eigen::MatrixXd sorted(n, q);  // the points sorted by their first coordinate, each coordinate contiguous
  for (Eigen::Index a = 0; a < n; ++a) sorted.row(a) = X.row(order[static_cast<std::size_t>(a)]);
  const RepulsionChunk pairs{sorted.data(), static_cast<std::size_t>(n), static_cast<std::size_t>(q), inv_r2,
                             cutoff, std::sqrt(cutoff), repulsion * 2.0 * inv_r2};
  // Fixed ranges of the sorted points, each summed on its own and added in order: the value and
  // gradient do not depend on the number of threads.
  const auto nn = static_cast<std::size_t>(n), qq = static_cast<std::size_t>(q);
  const std::size_t chunks = std::clamp<std::size_t>(nn / 1024, 1, 16);
  std::vector<double> sums(chunks, 0.0);
  std::vector<std::vector<double>> gradients(gradient != nullptr ? chunks : 0);
  parallel_for_each(0, chunks, [&](std::size_t c) {
    const std::size_t begin = nn * c / chunks, end = nn * (c + 1) / chunks, rows = pairs.reach(end) - begin;
    double* g = nullptr;
    if (gradient != nullptr) {
      gradients[c].assign(rows * qq, 0.0);
      g = gradients[c].data();
    }
    sums[c] = pairs.run(begin, end, g, rows);
  });
  double sum = 0.0;
  for (double s : sums) sum += s;
  if (gradient != nullptr) {
    Eigen::MatrixXd total = Eigen::MatrixXd::Zero(n, q);  // sorted order
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::size_t begin = nn * c / chunks, rows = gradients[c].size() / qq;
      total.middleRows(static_cast<Eigen::Index>(begin), static_cast<Eigen::Index>(rows)) +=
          Eigen::Map<const Eigen::MatrixXd>(gradients[c].data(), static_cast<Eigen::Index>(rows), q);
    }
    for (Eigen::Index a = 0; a < n; ++a) gradient->row(order[static_cast<std::size_t>(a)]) += total.row(a);
  }
  return repulsion * sum;
}

}  // namespace matlas::gp
