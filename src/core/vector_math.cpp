#include "core/vector_math.h"

#include <cmath>

#include "core/cpu_features.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MATLAS_LIBMVEC 1
#endif

#ifdef MATLAS_LIBMVEC
// libmvec's entry points (the x86-64 vector function ABI names for AVX-512 and AVX2); each is
// a glibc IFUNC that picks its implementation for the processor.
extern "C" {
__attribute__((target("avx512f"))) __m512d _ZGVeN8v_exp(__m512d);
__attribute__((target("avx2"))) __m256d _ZGVdN4v_exp(__m256d);
__attribute__((target("avx512f"))) __m512d _ZGVeN8v_expm1(__m512d);
__attribute__((target("avx2"))) __m256d _ZGVdN4v_expm1(__m256d);
__attribute__((target("avx512f"))) __m512d _ZGVeN8v_log(__m512d);
__attribute__((target("avx2"))) __m256d _ZGVdN4v_log(__m256d);
}
#endif

namespace matlas {

namespace {

#ifdef MATLAS_LIBMVEC
using Avx512Function = __m512d (*)(__m512d);
using Avx2Function = __m256d (*)(__m256d);

/// The tail is padded with a value in every function's domain (1), then dropped.
__attribute__((target("avx512f"))) void apply_avx512(Avx512Function f, double* v, std::size_t count) {
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) _mm512_storeu_pd(v + i, f(_mm512_loadu_pd(v + i)));
  if (i < count) {  // through a padded copy (plain loads and stores: nothing past the end is touched)
    alignas(64) double tail[8] = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
    for (std::size_t k = i; k < count; ++k) tail[k - i] = v[k];
    _mm512_store_pd(tail, f(_mm512_load_pd(tail)));
    for (std::size_t k = i; k < count; ++k) v[k] = tail[k - i];
  }
}

__attribute__((target("avx2"))) void apply_avx2(Avx2Function f, double* v, std::size_t count) {
  std::size_t i = 0;
  for (; i + 4 <= count; i += 4) _mm256_storeu_pd(v + i, f(_mm256_loadu_pd(v + i)));
  if (i < count) {
    alignas(32) double tail[4] = {1.0, 1.0, 1.0, 1.0};
    for (std::size_t k = i; k < count; ++k) tail[k - i] = v[k];
    _mm256_store_pd(tail, f(_mm256_load_pd(tail)));
    for (std::size_t k = i; k < count; ++k) v[k] = tail[k - i];
  }
}

/// 2: AVX-512, 1: AVX2, 0: neither (scalar libm).
int vector_kind() {
  static const int kind = cpu_has_avx512_skx() ? 2 : cpu_has_avx2_fma() ? 1 : 0;
  return kind;
}
#endif

template <class Scalar>
void apply_scalar(Scalar f, double* v, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) v[i] = f(v[i]);
}

}  // namespace

#ifdef MATLAS_LIBMVEC
#define MATLAS_VECTOR_FUNCTION(name, scalar, avx512, avx2)                \
  void name(double* values, std::size_t count) {                         \
    const int kind = vector_kind();                                      \
    if (kind == 2) return apply_avx512(avx512, values, count);           \
    if (kind == 1) return apply_avx2(avx2, values, count);               \
    apply_scalar([](double x) { return scalar(x); }, values, count);     \
  }
#else
#define MATLAS_VECTOR_FUNCTION(name, scalar, avx512, avx2) \
  void name(double* values, std::size_t count) { apply_scalar([](double x) { return scalar(x); }, values, count); }
#endif

MATLAS_VECTOR_FUNCTION(exp_in_place, std::exp, _ZGVeN8v_exp, _ZGVdN4v_exp)
MATLAS_VECTOR_FUNCTION(expm1_in_place, std::expm1, _ZGVeN8v_expm1, _ZGVdN4v_expm1)
MATLAS_VECTOR_FUNCTION(log_in_place, std::log, _ZGVeN8v_log, _ZGVdN4v_log)

#undef MATLAS_VECTOR_FUNCTION

}  // namespace matlas
