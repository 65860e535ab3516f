#include "manifold/dot_kernel.h"

#include <cstring>

namespace matlas {

namespace {
using Float8 = float __attribute__((vector_size(32)));
using Double8 = double __attribute__((vector_size(64)));
}  // namespace

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
double dot_f32_f64(const float* values, const double* weights, int n) {
  Double8 acc0 = {}, acc1 = {};
  int i = 0;
  for (; i + 16 <= n; i += 16) {
    Float8 a, b;
    Double8 wa, wb;
    std::memcpy(&a, values + i, sizeof a);
    std::memcpy(&b, values + i + 8, sizeof b);
    std::memcpy(&wa, weights + i, sizeof wa);
    std::memcpy(&wb, weights + i + 8, sizeof wb);
    acc0 += __builtin_convertvector(a, Double8) * wa;
    acc1 += __builtin_convertvector(b, Double8) * wb;
  }
  acc0 += acc1;
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) sum += acc0[k];
  for (; i < n; ++i) sum += static_cast<double>(values[i]) * weights[i];
  return sum;
}

}  // namespace matlas
