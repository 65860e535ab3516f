#pragma once
// MATLAS_SIMD_CLONES before a function definition compiles it for AVX-512 (x86-64-v4), AVX2 and
// baseline x86-64, the copy to run chosen once at load time (GCC function multiversioning; the
// AVX-512 copy took the build's centring step from 1.40 to 1.10 s, docs/BENCHMARKS.md). For the simple,
// vectorisable loops of the hot paths: a Release build targets baseline x86-64 (SSE2), where
// for instance 64-bit integer compares and double-to-byte masks do not vectorise.
// Left out under AddressSanitizer (which does not follow the load-time choice) and other
// compilers.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MATLAS_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define MATLAS_SIMD_CLONES
#endif
