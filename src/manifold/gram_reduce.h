#pragma once
// The ranks of a distributed pass (accumulate_gram with a PassShare per rank) add up their
// results: the Gram matrices and albedo curves are sums over columns, so the ranks' partial sums
// add up to the whole (Communicator::sum, in double: the same to rounding as one process's
// sums, whose blocks are added in another order); the mask, the means and the file hashes are
// per column or per byte range, gathered on rank 0 in rank order (exactly one process's mask and
// means: the blocks are the same).
#include <cstdint>
#include <vector>

#include "core/communicator.h"
#include "manifold/gram.h"

namespace matlas {

/// Turns each rank's share `g` into the whole pass's result. On every rank: gram, layout_gram,
/// albedo and kept_columns. On rank 0 only: kept, mean, hashes and [first_value, end_value) of
/// the whole pass; the other ranks keep their share's. With more than one rank, hashes[i] is the
/// xxh3-64 of the ranks' digests of their byte ranges of file i (8 bytes each, in rank order),
/// not of the file's bytes (no rank reads the whole file). Returns every rank's kept columns, in
/// rank order (where each rank's data starts in the model). Throws on every rank when no column
/// is kept.
std::vector<std::uint64_t> reduce_gram(GramResult& g, bool separate_layout_gram, Communicator& comm);

}  // namespace matlas
