#pragma once
// MATLAS_SIMD_CLONES before a function definition compiles it for AVX2 and for baseline x86-64,
// the copy to run chosen once at load time (GCC function multiversioning). For the simple,
// vectorisable loops of the hot paths: a Release build targets baseline x86-64 (SSE2), where
// for instance 64-bit integer compares and double-to-byte masks do not vectorise.
// Left out under AddressSanitizer (which does not follow the load-time choice) and other
// compilers.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MATLAS_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MATLAS_SIMD_CLONES
#endif
