#pragma once
// S += A A^T for row-major blocks A (n materials x k columns): the Gram update of a build pass.
// OpenBLAS's dsyrk does not speed up with threads for this thin shape (n ~ 100), so each block's
// columns are cut into fixed slices that the workers take as they become free, each slice a
// single-threaded dsyrk into its own scratch. Only upper triangles are computed.
//
// The slices' products are added to one sum with compensation (a high part and the rounding
// errors of its additions, Knuth's TwoSum): the sum is the exact one to about 2^-100 of its terms,
// so its rounding to double does not depend on the order of the additions: not on scheduling or
// the number of threads, and not on how a pass is split across processes (each summing its
// blocks, then the processes' sums added with the same compensation,
// Communicator::sum_compensated): a distributed pass gives the single process's Gram matrix bit
// for bit, and the latent placements fitted to it the same layouts.
#include <cstddef>
#include <mutex>
#include <vector>

#include <Eigen/Core>

#include "core/huge_pages.h"
#include "manifold/column_blocks.h"

namespace matlas {

class GramAccumulator {
public:
  /// Columns per slice (n x 1024 doubles: 800 KB for n = 100). dsyrk is as fast on 512 columns
  /// as on 4096 (bench_manifold BM_GramSliceWidth), and smaller slices balance the two cores
  /// better: a block's ~3100 kept columns were one slice of 2048 and one of ~1000 per Gram matrix
  /// with 2048-column slices.
  static constexpr std::size_t kSlice = 1024;
  /// Number of slices of a block of `columns` columns.
  static std::size_t slices(std::size_t columns) { return (columns + kSlice - 1) / kSlice; }

  /// For n materials and blocks of at most max_columns columns.
  GramAccumulator(Eigen::Index n, std::size_t max_columns);

  /// Adds slice s of block a. Different slices may be added from different threads at once.
  void add_slice(const BlockMatrix& a, std::size_t s) {
    add_slice(a.data(), static_cast<std::size_t>(a.cols()), static_cast<std::size_t>(a.cols()), s);
  }
  /// The same for a row-major n x columns block whose rows start ld doubles apart.
  void add_slice(const double* a, std::size_t ld, std::size_t columns, std::size_t s);
  /// The same for single-precision data: the slice's product in single precision (ssyrk; 1.7x
  /// the rate of dsyrk on these shapes), added to the double accumulator. Each slice adds an
  /// error of about sqrt(1024) float roundings of its own entries; over a pass's thousands of
  /// slices the sum's relative error stays near 1e-7 (tests/manifold/test_gram.cpp measures it).
  void add_slice(const float* a, std::size_t ld, std::size_t columns, std::size_t s);

  /// The sum so far, symmetric, rounded to double.
  Eigen::MatrixXd total() const;
  /// The sum so far rounded to double into `value` and what the rounding left out into `rest`
  /// (value + rest is the compensated sum; both symmetric): GramResult::gram and gram_low.
  void total(Eigen::MatrixXd& value, Eigen::MatrixXd& rest) const;

private:
  template <class T>
  void add_product(const T* product);

  Eigen::Index n_;
  /// The upper triangles of the sum's high part and of its compensation.
  Eigen::MatrixXd high_, low_;
  std::mutex mutex_;  ///< one product added to the sum at a time
  /// Per slice, the product being added (one task per slice at a time; per slice rather than per
  /// thread, so that the scratch does not grow with the number of workers): double or single.
  std::vector<HugePageVector<double>> product_;
  std::vector<HugePageVector<float>> product_single_;
};

/// high += value with its rounding error added to low (TwoSum): high + low keeps the exact sum.
inline void add_compensated(double& high, double& low, double value) {
  const double sum = high + value;
  const double back = sum - high;
  low += (high - (sum - back)) + (value - back);
  high = sum;
}

/// value + low rounded to double into value, what the rounding left out into low (their sum
/// unchanged): the form a compensated Gram is kept in (GramResult::gram, gram_low).
void round_compensated(Eigen::MatrixXd& value, Eigen::MatrixXd& low);

/// upper += upper triangle of A A^T, using all workers.
void add_gram_upper(const BlockMatrix& a, Eigen::MatrixXd& upper);

/// Copies the upper triangle of S into its lower triangle.
void symmetrize_from_upper(Eigen::MatrixXd& s);

}  // namespace matlas
