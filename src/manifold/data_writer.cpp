#include "formats/half_float.h"
#include "manifold/data_writer.h"

#include <algorithm>
#include <cmath>

#include "core/cpu_features.h"
#include "manifold/column_blocks.h"

#if defined(__x86_64__)
#include <immintrin.h>
#define MATLAS_X86 1
#endif

namespace matlas {

namespace {

/// out[c * n + i] = float(values[i * stride + columns[c]]) for rows i < rows and the tile's
/// `count` kept columns; adds sum x^2 and sum (float(x) - x)^2 to norm2 and error2. Row by row: each row's reads are
/// contiguous and the tile's output stays in L1 (column by column would read rows a
/// power-of-two stride apart and thrash L1). Four partial sums: one would be latency-bound.
void transpose_tile_scalar(const double* values, std::size_t stride, std::size_t rows, std::size_t n,
                           const std::size_t* columns, std::size_t count, float* out, double& norm2, double& error2) {
  double e[4] = {0, 0, 0, 0}, v[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < rows; ++i) {
    const double* row = values + i * stride;
    for (std::size_t c = 0; c < count; ++c) {
      const double exact = row[columns[c]];
      const auto rounded = static_cast<float>(exact);
      out[c * n + i] = rounded;
      v[c % 4] += exact * exact;
      e[c % 4] += (rounded - exact) * (rounded - exact);
    }
  }
  norm2 += v[0] + v[1] + v[2] + v[3];
  error2 += e[0] + e[1] + e[2] + e[3];
}

#ifdef MATLAS_X86
/// The same for a tile of kTile consecutive kept columns starting at `first`: 4 x 4 blocks are
/// loaded as four rows of four doubles, converted, transposed in registers and stored as four
/// columns of four floats.
__attribute__((target("avx2,fma"))) void transpose_full_tile_avx2(const double* values, std::size_t stride,
                                                                  std::size_t n, std::size_t first, float* out,
                                                                  double& norm2, double& error2) {
  __m256d v_acc = _mm256_setzero_pd(), e_acc = _mm256_setzero_pd();
  const std::size_t n4 = n / 4 * 4;
  for (std::size_t i = 0; i < n4; i += 4) {
    const double* r = values + i * stride + first;
    for (std::size_t c = 0; c < DataWriter::kTile; c += 4) {
      __m128 f[4];
      for (int k = 0; k < 4; ++k) {
        const __m256d x = _mm256_loadu_pd(r + static_cast<std::size_t>(k) * stride + c);
        f[k] = _mm256_cvtpd_ps(x);
        const __m256d d = _mm256_sub_pd(_mm256_cvtps_pd(f[k]), x);
        v_acc = _mm256_fmadd_pd(x, x, v_acc);
        e_acc = _mm256_fmadd_pd(d, d, e_acc);
      }
      _MM_TRANSPOSE4_PS(f[0], f[1], f[2], f[3]);
      for (int k = 0; k < 4; ++k) _mm_storeu_ps(out + (c + static_cast<std::size_t>(k)) * n + i, f[k]);
    }
  }
  alignas(32) double v[4], e[4];
  _mm256_store_pd(v, v_acc);
  _mm256_store_pd(e, e_acc);
  norm2 += v[0] + v[1] + v[2] + v[3];
  error2 += e[0] + e[1] + e[2] + e[3];
  // Rows left over from the groups of four.
  std::size_t columns[DataWriter::kTile];
  for (std::size_t c = 0; c < DataWriter::kTile; ++c) columns[c] = first + c;
  if (n4 < n)
    transpose_tile_scalar(values + n4 * stride, stride, n - n4, n, columns, DataWriter::kTile, out + n4, norm2, error2);
}

#endif

}  // namespace

DataWriter::DataWriter(SafetensorsWriter& writer, std::size_t n, DType storage)
    : DataWriter([&writer](const void* data, std::size_t bytes) { writer.append(data, bytes); }, n, storage) {}

DataWriter::DataWriter(Sink sink, std::size_t n, DType storage) : sink_(std::move(sink)), n_(n), storage_(storage) {}

void DataWriter::prepare(const ColumnBlock& block) {
  const std::size_t tiles = (block.count + kTile - 1) / kTile;
  tile_start_.assign(tiles + 1, 0);
  for (std::size_t t = 0; t < tiles; ++t) {
    std::size_t kept = 0;
    for (std::size_t j = t * kTile; j < std::min(block.count, (t + 1) * kTile); ++j) kept += block.kept[j];
    tile_start_[t + 1] = tile_start_[t] + kept;
  }
  out_f32_.resize(tile_start_[tiles] * n_);
  if (storage_ == DType::F16) out_f16_.resize(out_f32_.size());
  tile_error_.assign(tiles, {0.0, 0.0});
}

void DataWriter::visit(const ColumnBlock& block, std::size_t first, std::size_t last) {
  static_assert(kSweepColumns % kTile == 0);
  std::size_t columns[kTile];
  for (std::size_t t = first / kTile; t < (last + kTile - 1) / kTile; ++t) {
    std::size_t count = 0;
    for (std::size_t j = t * kTile; j < std::min(block.count, (t + 1) * kTile); ++j)
      if (block.kept[j]) columns[count++] = j;
    double error2 = 0.0, norm2 = 0.0;
    float* out = out_f32_.data() + tile_start_[t] * n_;
    const double* values = block.values.data();
#ifdef MATLAS_X86
    if (count == kTile && cpu_has_avx2_fma())
      transpose_full_tile_avx2(values, block.count, n_, t * kTile, out, norm2, error2);
    else
#endif
      transpose_tile_scalar(values, block.count, n_, n_, columns, count, out, norm2, error2);
    if (storage_ == DType::F16) {
      // The value stored is half(float(x)): add the second rounding.
      double e[4] = {0, 0, 0, 0};
      for (std::size_t k = tile_start_[t] * n_; k < tile_start_[t + 1] * n_; ++k) {
        out_f16_[k] = float_to_half(out_f32_[k]);
        const double rounding = static_cast<double>(half_to_float(out_f16_[k])) - out_f32_[k];
        e[k % 4] += rounding * rounding;
      }
      error2 += e[0] + e[1] + e[2] + e[3];
    }
    tile_error_[t] = {error2, norm2};
  }
}

void DataWriter::finish(const ColumnBlock&) {
  for (const auto& [e, v] : tile_error_) {
    error2_ += e;
    norm2_ += v;
  }
  if (storage_ == DType::F16) sink_(out_f16_.data(), out_f16_.size() * 2u);
  else sink_(out_f32_.data(), out_f32_.size() * 4u);
}

double DataWriter::relative_error() const { return norm2_ > 0 ? std::sqrt(error2_ / norm2_) : 0.0; }

}  // namespace matlas
