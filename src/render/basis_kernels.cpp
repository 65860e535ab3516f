#include "render/basis_kernels.h"

#include <vector>

#include "core/cpu_features.h"
#include "formats/half_float.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define MATLAS_X86 1
#endif

namespace matlas::render::detail {

const float* half_table() {
  static const std::vector<float> table = [] {
    std::vector<float> t(65536);
    for (std::uint32_t h = 0; h < 65536; ++h) t[h] = half_to_float(static_cast<std::uint16_t>(h));
    return t;
  }();
  return table.data();
}

namespace {

// --- accumulation kernels: acc[0, len) += sum_i w[i] * row_i[begin, begin + len) -------------

void accumulate_f32_portable(const float* values, std::size_t stride, std::size_t begin, std::size_t len,
                             const float* w, int n, float* acc) {
  for (int i = 0; i < n; ++i) {
    const float wi = w[i];
    if (wi == 0.0f) continue;
    const float* row = values + static_cast<std::size_t>(i) * stride + begin;
    for (std::size_t j = 0; j < len; ++j) acc[j] += wi * row[j];
  }
}

void accumulate_f16_portable(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                             const float* w, int n, float* acc) {
  const float* table = half_table();
  for (int i = 0; i < n; ++i) {
    const float wi = w[i];
    if (wi == 0.0f) continue;
    const std::uint16_t* row = values + static_cast<std::size_t>(i) * stride + begin;
    for (std::size_t j = 0; j < len; ++j) acc[j] += wi * table[row[j]];
  }
}

#ifdef MATLAS_X86
// The AVX2 kernels add four rows per pass over the accumulator (one load and one store of acc
// per four products), which keeps them memory-bound rather than bound by L1 traffic.
template <class Load>
__attribute__((target("avx2,fma"), always_inline)) inline void accumulate_rows_avx2(Load load, std::size_t len,
                                                                                  const float* w, int n, float* acc) {
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256 w0 = _mm256_set1_ps(w[i]), w1 = _mm256_set1_ps(w[i + 1]), w2 = _mm256_set1_ps(w[i + 2]),
                 w3 = _mm256_set1_ps(w[i + 3]);
    for (std::size_t j = 0; j + 8 <= len; j += 8) {
      __m256 a = _mm256_loadu_ps(acc + j);
      a = _mm256_fmadd_ps(w0, load(i, j), a);
      a = _mm256_fmadd_ps(w1, load(i + 1, j), a);
      a = _mm256_fmadd_ps(w2, load(i + 2, j), a);
      a = _mm256_fmadd_ps(w3, load(i + 3, j), a);
      _mm256_storeu_ps(acc + j, a);
    }
  }
  for (; i < n; ++i) {
    const __m256 wi = _mm256_set1_ps(w[i]);
    for (std::size_t j = 0; j + 8 <= len; j += 8)
      _mm256_storeu_ps(acc + j, _mm256_fmadd_ps(wi, load(i, j), _mm256_loadu_ps(acc + j)));
  }
}

__attribute__((target("avx2,fma"))) void accumulate_f32_avx2(const float* values, std::size_t stride,
                                                             std::size_t begin, std::size_t len, const float* w,
                                                             int n, float* acc) {
  const std::size_t vec = len / 8 * 8;
  accumulate_rows_avx2(
      [&](int i, std::size_t j) __attribute__((target("avx2,fma"))) {
        return _mm256_loadu_ps(values + static_cast<std::size_t>(i) * stride + begin + j);
      },
      vec, w, n, acc);
  for (int i = 0; i < n; ++i)
    for (std::size_t j = vec; j < len; ++j) acc[j] += w[i] * values[static_cast<std::size_t>(i) * stride + begin + j];
}

__attribute__((target("avx2,fma,f16c"))) void accumulate_f16_f16c(const std::uint16_t* values, std::size_t stride,
                                                                  std::size_t begin, std::size_t len, const float* w,
                                                                  int n, float* acc) {
  const std::size_t vec = len / 8 * 8;
  accumulate_rows_avx2(
      [&](int i, std::size_t j) __attribute__((target("avx2,fma,f16c"))) {
        return _mm256_cvtph_ps(
            _mm_loadu_si128(reinterpret_cast<const __m128i*>(values + static_cast<std::size_t>(i) * stride + begin + j)));
      },
      vec, w, n, acc);
  const float* table = half_table();
  for (int i = 0; i < n; ++i)
    for (std::size_t j = vec; j < len; ++j) acc[j] += w[i] * table[values[static_cast<std::size_t>(i) * stride + begin + j]];
}

#endif

}  // namespace

void accumulate_f32(const float* values, std::size_t stride, std::size_t begin, std::size_t len, const float* w,
                    int n, float* acc) {
#ifdef MATLAS_X86
  if (cpu_has_avx2_fma()) return accumulate_f32_avx2(values, stride, begin, len, w, n, acc);
#endif
  accumulate_f32_portable(values, stride, begin, len, w, n, acc);
}

void accumulate_f16(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                    const float* w, int n, float* acc) {
#ifdef MATLAS_X86
  if (cpu_has_avx2_fma_f16c()) return accumulate_f16_f16c(values, stride, begin, len, w, n, acc);
#endif
  accumulate_f16_portable(values, stride, begin, len, w, n, acc);
}

}  // namespace matlas::render::detail
