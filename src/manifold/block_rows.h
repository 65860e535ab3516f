#pragma once
// Reading the rows of a column block: columns [first, first + count) of a range of materials,
// each material's values hashed, checked and scaled to physical units in one pass per
// cache-resident chunk, while the column sums and the validity of the rows read are gathered.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <xxhash.h>

#include "manifold/block_prefetch.h"
#include "manifold/column_blocks.h"

namespace matlas {

/// One streaming xxh3-64 state per material.
class FileHashers {
public:
  explicit FileHashers(std::size_t n);
  ~FileHashers();
  FileHashers(const FileHashers&) = delete;
  FileHashers& operator=(const FileHashers&) = delete;
  XXH3_state_t* const* data() { return states_.data(); }
  /// The hash of everything each state has seen.
  std::vector<std::uint64_t> digests() const;

private:
  std::vector<XXH3_state_t*> states_;
};

/// What one group of rows of a block adds up to: per column, the sum of the rows' values and
/// whether every row measures it (stored value >= 0).
struct RowGroupSums {
  double* column_sums = nullptr;  ///< count entries, overwritten; may be null (not gathered)
  std::uint8_t* kept = nullptr;   ///< count entries, overwritten with 1 where every row >= 0; required
};

/// Where read_block_rows takes a block's values: from the files (no prefetch), or from block
/// `block` of a prefetch, which must be the block of columns asked for.
struct PrefetchedBlock {
  BlockPrefetch* prefetch = nullptr;
  std::size_t block = 0;
};

/// Reads rows [row_begin, row_end) of block columns [first, first + count) into the same rows of
/// `values` (n x count, physical units). hashers[i], when hashers is not null, is updated with
/// material i's stored bytes: calling this for consecutive blocks hashes each whole file.
/// Throws matlas::Error naming the file on a read error or a non-finite value.
void read_block_rows(const MaterialSet& set, std::size_t first, std::size_t count, std::size_t row_begin,
                     std::size_t row_end, BlockMatrix& values, XXH3_state_t* const* hashers, RowGroupSums sums,
                     PrefetchedBlock prefetched = {});

}  // namespace matlas
