#pragma once
// The pass of a build: validity mask, mean, centred Gram matrices, albedo curves and file hashes
// of a MaterialSet, in double.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "manifold/layout_transform.h"
#include "manifold/material_set.h"

namespace matlas {

/// Wall-clock seconds of a pass's steps, which run one after the other per block (each on all
/// workers), so they add up to the pass.
struct PassSteps {
  double read = 0;      ///< reading the first block, and each block's mask (the rest of the reading
                        ///< runs beside the previous block's products, counted there)
  double sweep = 0;     ///< means, the raw visitor (a build's data), centring, layout transform
  double products = 0;  ///< Gram matrices, albedo curves, the raw visitor's output, with the next
                        ///< block's files read alongside
};

struct GramResult {
  /// The value indices this result covers, [first_value, end_value): all of them, or one rank's
  /// share of a distributed pass (PassShare), whose sums the ranks then add up (gram_reduce.h).
  std::size_t first_value = 0, end_value = 0;
  std::vector<bool> kept;         ///< per value index: every material measured (false outside the share)
  std::size_t kept_columns = 0;
  Eigen::VectorXd mean;           ///< per kept column, in value-index order
  Eigen::MatrixXd gram;           ///< n x n centred Gram of the linear data
  Eigen::MatrixXd layout_gram;    ///< n x n centred Gram of the transformed data
  /// What rounding the sums to double left out (gram + gram_low is the compensated sum,
  /// gram_update.h): the ranks of a distributed pass add these too, so that their Grams are the
  /// single process's bit for bit (gram_reduce.h).
  Eigen::MatrixXd gram_low, layout_gram_low;
  Eigen::MatrixXd albedo;         ///< n x (kAlbedoAngles * 3) directional albedo curves of the kept data
  std::vector<std::uint64_t> hashes;  ///< xxh3-64 of each input file's value bytes (of the share's bytes)
  PassSteps steps;
};

struct ColumnBlock;

/// Sees the raw data (physical units, before centring) of every block of the pass: prepare()
/// once per block, then visit() from several threads at once on disjoint column ranges that
/// together cover the block (each range while it is in cache; range bounds are multiples of
/// kSweepColumns), then finish() (on a worker, alongside the block's Gram slices and albedo
/// curves, while the next block is read into block.values: finish must not read block.values;
/// visit copies what it needs). A build writes the model's data this way, in
/// the same pass.
struct RawBlockVisitor {
  static constexpr std::size_t kSweepColumns = 512;
  virtual ~RawBlockVisitor() = default;
  virtual void prepare(const ColumnBlock&) {}
  virtual void visit(const ColumnBlock& block, std::size_t first, std::size_t last) = 0;
  virtual void finish(const ColumnBlock&) {}
};

/// Which blocks of the pass this process reads: share `part` of `parts` contiguous shares of the
/// blocks (a distributed build: one share per rank). The default is the whole pass.
struct PassShare {
  int part = 0, parts = 1;
};

/// Columns per block of a pass over n materials when none is asked for (block_columns 0). Up to
/// 511 materials, 4096 (n = 100: a 3 MB block that stays in the last-level cache between the
/// pass's steps; 8192 was slower); from 512 on, 16384, each file read 128 KB at a time, which
/// at n = 1000 takes the build's system time from 16-27 s to 11-13 s and its median wall time
/// from 73 to 68 s (through the page cache: CHANGELOG.md, thirty-sixth session), narrowed to a multiple
/// of the Gram's slices (1024 columns) so that a block stays within 256 MB (at least 4096).
std::size_t default_block_columns(std::size_t n);

/// block_columns when it is not 0, else default_block_columns(n).
inline std::size_t resolved_block_columns(std::size_t block_columns, std::size_t n) {
  return block_columns != 0 ? block_columns : default_block_columns(n);
}

/// How a pass reads the files: automatic (the default) reads ahead around the page cache
/// (BlockPrefetch) when the pass's share of the data exceeds the machine's memory, else through the
/// page cache with the kernel's read-ahead (ReadAhead); page_cache and prefetch ask for one.
enum class PassReads { automatic, page_cache, prefetch };

/// One streaming pass over the set, block_columns columns of all materials at a time (a block
/// and what is derived from it are meant to stay in the last-level cache between the pass's
/// steps). Results do not depend on the number of threads. The blocks are the same whatever the
/// share, so a share's means and raw blocks are exactly those of the whole pass; its Gram
/// matrices and albedo curves are partial sums. block_columns 0: default_block_columns. Throws
/// when the whole pass (not a share) keeps no column.
GramResult accumulate_gram(const MaterialSet& set, const LayoutTransform& layout, std::size_t block_columns,
                           ProgressSink& progress, RawBlockVisitor* raw = nullptr, PassShare share = {},
                           PassReads reads = PassReads::automatic);

/// Throws matlas::Error when no column is kept (the inputs have no common measurements).
void require_kept_columns(const GramResult& g);

}  // namespace matlas
