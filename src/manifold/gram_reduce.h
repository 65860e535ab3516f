#pragma once
// The ranks of a distributed pass (accumulate_gram with a PassShare per rank) add up their
// results: the Gram matrices and albedo curves are sums over columns, so the ranks' partial sums
// add up to the whole (Communicator::sum, in double: the same to rounding as one process's
// sums, whose blocks are added in another order); the mask, the means and the file hashes are
// per column or per file: the mask and the means stay with their rank (each writes its slices of
// the model, data_shares.h; they are exactly one process's: the blocks are the same), the file
// hashes of the ranks' byte ranges go to rank 0.
#include <cstdint>
#include <vector>

#include "core/communicator.h"
#include "manifold/gram.h"

namespace matlas {

/// Adds up the ranks' shares `g`: afterwards gram, layout_gram, albedo and kept_columns are the
/// whole pass's on every rank; kept, mean and [first_value, end_value) stay the share's. On rank
/// 0, with more than one rank, hashes[i] becomes the xxh3-64 of the ranks' digests of their byte
/// ranges of file i (8 bytes each, in rank order), not of the file's bytes (no rank reads the
/// whole file). Returns every rank's kept columns, in rank order (where each rank's slices start
/// in the model). Throws on every rank when no column is kept.
std::vector<std::uint64_t> reduce_gram(GramResult& g, bool separate_layout_gram, Communicator& comm);

}  // namespace matlas
