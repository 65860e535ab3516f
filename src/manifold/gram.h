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
  std::vector<bool> kept;         ///< per value index: every material measured
  std::size_t kept_columns = 0;
  Eigen::VectorXd mean;           ///< per kept column, in value-index order
  Eigen::MatrixXd gram;           ///< n x n centred Gram of the linear data
  Eigen::MatrixXd layout_gram;    ///< n x n centred Gram of the transformed data
  Eigen::MatrixXd albedo;         ///< n x (kAlbedoAngles * 3) directional albedo curves of the kept data
  std::vector<std::uint64_t> hashes;  ///< xxh3-64 of each input file's value bytes
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

/// One streaming pass over the set, block_columns columns of all materials at a time (a block
/// and what is derived from it are meant to stay in the last-level cache between the pass's
/// steps). Results do not depend on the number of threads.
GramResult accumulate_gram(const MaterialSet& set, const LayoutTransform& layout, std::size_t block_columns,
                           ProgressSink& progress, RawBlockVisitor* raw = nullptr);

}  // namespace matlas
