#pragma once
// Small statistics for the evaluation: ranks, rank correlation, summaries.
#include <span>
#include <vector>

namespace matlas::eval {

/// `count` of the indices 0..n-1, evenly spread (k n / count); all of them when count <= 0 or >= n.
std::vector<int> spread_indices(int n, int count);

/// Ranks 1..n with ties given their average rank.
std::vector<double> average_ranks(std::span<const double> values);

/// Pearson correlation; NaN when fewer than 2 values or either input is constant.
double pearson(std::span<const double> a, std::span<const double> b);

/// Spearman rank correlation (Pearson correlation of the average ranks); NaN as pearson().
double spearman(std::span<const double> a, std::span<const double> b);

struct Summary {
  double mean = 0, median = 0, max = 0, min = 0;
  std::size_t count = 0;
};
/// Mean, median, min and max (all 0 for an empty input).
Summary summarize(std::span<const double> values);

}  // namespace matlas::eval
