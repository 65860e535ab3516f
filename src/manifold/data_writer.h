#pragma once
// DataWriter: during a build's pass, writes each block's inputs into the model's "data" tensor
// (column-interleaved: for every kept column, the n materials' values as float32 or float16) and
// measures the storage rounding error.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "formats/safetensors.h"
#include "manifold/gram.h"

namespace matlas {

class DataWriter final : public RawBlockVisitor {
public:
  /// Appends to the current growing tensor of `writer`; n materials; storage F32 or F16.
  DataWriter(SafetensorsWriter& writer, std::size_t n, DType storage);

  void prepare(const ColumnBlock& block) override;
  void visit(const ColumnBlock& block, std::size_t first, std::size_t last) override;
  void finish(const ColumnBlock& block) override;

  /// Relative L2 error of the stored values against the double inputs so far.
  double relative_error() const;

  /// Columns per transposed tile; each tile's kept columns are found in prepare().
  static constexpr std::size_t kTile = 64;

private:
  SafetensorsWriter& writer_;
  std::size_t n_;
  DType storage_;
  std::vector<std::size_t> tile_start_;  ///< first output column of each tile
  std::vector<float> out_f32_;
  std::vector<std::uint16_t> out_f16_;
  std::vector<std::pair<double, double>> tile_error_;  ///< (error^2, value^2) per tile
  double error2_ = 0.0, norm2_ = 0.0;
};

}  // namespace matlas
