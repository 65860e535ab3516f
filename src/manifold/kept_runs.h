#pragma once
// The kept columns of a block as runs of consecutive columns, each mapped to its place in the
// compacted block (kept columns only). Dropped columns (not measured in every material) are about
// a quarter of MERL's bins and contribute nothing to a Gram matrix: compacting them out before
// the products saves that share of the flops.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace matlas {

/// Block columns [first, first + count) are kept, and go to compacted columns [out, out + count).
struct KeptRun {
  std::size_t first = 0, count = 0, out = 0;
};

struct KeptRuns {
  std::vector<KeptRun> runs;
  /// Runs never cross a multiple of the range length given to kept_runs(): range c's runs are
  /// runs[range_begin[c] .. range_begin[c + 1]).
  std::vector<std::size_t> range_begin;
  std::size_t kept = 0;  ///< compacted columns in all

  std::span<const KeptRun> range(std::size_t c) const {
    return {runs.data() + range_begin[c], range_begin[c + 1] - range_begin[c]};
  }
};

/// The runs of kept[0 .. count) (1 = kept), split at multiples of `range`.
KeptRuns kept_runs(const std::uint8_t* kept, std::size_t count, std::size_t range);

}  // namespace matlas
