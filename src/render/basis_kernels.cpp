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

// --- accumulation kernels: acc[0, len) += sum_i w[i] * row_{rows[i]}[begin, begin + len) -----

/// Start of row rows[i] in `values`.
template <class T>
const T* row_start(const T* values, std::size_t stride, std::size_t begin, const int* rows, int i) {
  return values + static_cast<std::size_t>(rows[i]) * stride + begin;
}

void accumulate_f32_portable(const float* values, std::size_t stride, std::size_t begin, std::size_t len,
                             const int* rows, const float* w, int n, float* acc) {
  for (int i = 0; i < n; ++i) {
    const float wi = w[i];
    if (wi == 0.0f) continue;
    const float* row = row_start(values, stride, begin, rows, i);
    for (std::size_t j = 0; j < len; ++j) acc[j] += wi * row[j];
  }
}

void accumulate_f16_portable(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                             const int* rows, const float* w, int n, float* acc) {
  const float* table = half_table();
  for (int i = 0; i < n; ++i) {
    const float wi = w[i];
    if (wi == 0.0f) continue;
    const std::uint16_t* row = row_start(values, stride, begin, rows, i);
    for (std::size_t j = 0; j < len; ++j) acc[j] += wi * table[row[j]];
  }
}

#ifdef MATLAS_X86
/// Eight values as floats, from float32 or float16 storage.
struct LoadF32 {
  __attribute__((target("avx2,fma,f16c"))) __m256 operator()(const float* p) const { return _mm256_loadu_ps(p); }
  float operator()(const float* p, std::size_t j) const { return p[j]; }
};
struct LoadF16 {
  __attribute__((target("avx2,fma,f16c"))) __m256 operator()(const std::uint16_t* p) const {
    return _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
  }
  float operator()(const std::uint16_t* p, std::size_t j) const { return half_table()[p[j]]; }
};

// One row per pass over the accumulator (which stays in L1): one sequential stream at a time
// (faster than four rows per pass when measured: CHANGELOG.md). F16C is in the target of both
// (every AVX2 CPU has it) so that the float16 load is inlined.
template <class T, class Load>
__attribute__((target("avx2,fma,f16c"))) void accumulate_avx2(const T* values, std::size_t stride, std::size_t begin,
                                                              std::size_t len, const int* rows, const float* w, int n,
                                                              float* acc) {
  const Load load;
  const std::size_t vec = len / 8 * 8;
  for (int i = 0; i < n; ++i) {
    const __m256 wi = _mm256_set1_ps(w[i]);
    const T* r = row_start(values, stride, begin, rows, i);
    for (std::size_t j = 0; j < vec; j += 8)
      _mm256_storeu_ps(acc + j, _mm256_fmadd_ps(wi, load(r + j), _mm256_loadu_ps(acc + j)));
    for (std::size_t j = vec; j < len; ++j) acc[j] += w[i] * load(r, j);
  }
}

#endif

}  // namespace

void accumulate_f32(const float* values, std::size_t stride, std::size_t begin, std::size_t len, const int* rows,
                    const float* w, int n, float* acc) {
#ifdef MATLAS_X86
  if (cpu_has_avx2_fma_f16c()) return accumulate_avx2<float, LoadF32>(values, stride, begin, len, rows, w, n, acc);
#endif
  accumulate_f32_portable(values, stride, begin, len, rows, w, n, acc);
}

void accumulate_f16(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                    const int* rows, const float* w, int n, float* acc) {
#ifdef MATLAS_X86
  if (cpu_has_avx2_fma_f16c())
    return accumulate_avx2<std::uint16_t, LoadF16>(values, stride, begin, len, rows, w, n, acc);
#endif
  accumulate_f16_portable(values, stride, begin, len, rows, w, n, acc);
}

}  // namespace matlas::render::detail
