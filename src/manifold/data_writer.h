#pragma once
// DataWriter: during a build's pass, writes each block's inputs into the model's "data" tensor
// (column-interleaved: for every kept column, the n materials' values as float32 or float16) and
// measures the storage rounding error.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "core/huge_pages.h"
#include "formats/safetensors.h"
#include "manifold/gram.h"

namespace matlas {

class DataWriter final : public RawBlockVisitor {
public:
  /// Where each block's bytes go, in order: the model's growing "data" tensor, or (a rank of a
  /// distributed build other than 0) a file of the rank's share, copied into the model later.
  using Sink = std::function<void(const void* data, std::size_t bytes)>;
  /// Appends to the current growing tensor of `writer`; n materials; storage F32 or F16.
  DataWriter(SafetensorsWriter& writer, std::size_t n, DType storage);
  DataWriter(Sink sink, std::size_t n, DType storage);

  void prepare(const ColumnBlock& block) override;
  void visit(const ColumnBlock& block, std::size_t first, std::size_t last) override;
  void finish(const ColumnBlock& block) override;

  /// Relative L2 error of the stored values against the double inputs so far.
  double relative_error() const;
  /// Its parts, sum (stored - x)^2 and sum x^2 (a distributed build adds them up over the ranks).
  std::pair<double, double> error_sums() const { return {error2_, norm2_}; }

  /// Columns per transposed tile; each tile's kept columns are found in prepare().
  static constexpr std::size_t kTile = 64;

private:
  Sink sink_;
  std::size_t n_;
  DType storage_;
  std::vector<std::size_t> tile_start_;  ///< first output column of each tile
  HugePageVector<float> out_f32_;
  HugePageVector<std::uint16_t> out_f16_;
  std::vector<std::pair<double, double>> tile_error_;  ///< (error^2, value^2) per tile
  double error2_ = 0.0, norm2_ = 0.0;
};

}  // namespace matlas
