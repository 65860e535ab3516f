#pragma once
// What the processor can run, asked once per process. Code with hand-written AVX2 kernels
// (`__attribute__((target(...)))`) calls these to choose between the kernel and the portable
// loop; MATLAS_SIMD_CLONES (simd_clones.h) is the compiler-chosen alternative for simple loops.
// Both return false on processors other than x86.

namespace matlas {

/// AVX2 and FMA.
bool cpu_has_avx2_fma();
/// AVX2, FMA and F16C (half-precision conversions).
bool cpu_has_avx2_fma_f16c();
/// AVX-512 F, CD, BW, DQ and VL (the "Skylake-X" set).
bool cpu_has_avx512_skx();

}  // namespace matlas
