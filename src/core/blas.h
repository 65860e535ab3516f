#pragma once
// OpenBLAS, loaded on first use (dlopen of libopenblas.so.0) so that matlas can choose its
// kernels before the library initialises.
//
// Why: Debian 12's OpenBLAS 0.3.21 (a DYNAMIC_ARCH build) picks its kernels by processor model
// and falls back to its slowest, SSE3 kernels ("Prescott") on models newer than itself. On a
// 2023 Xeon (Emerald Rapids, family 6 model 207) dsyrk of the build's Gram slices ran at
// 9.5 GFLOP/s with those and at 31-38 GFLOP/s with the SkylakeX kernels (docs/BENCHMARKS.md).
// Unless the user set OPENBLAS_CORETYPE (OpenBLAS's own switch, which always wins), matlas sets
// it for the load from the processor's features (`kernel_for`) and removes it again afterwards,
// so child processes see the environment unchanged.
//
// OpenBLAS runs single-threaded: matlas splits its work over its own workers (core/parallel.h)
// and calls OpenBLAS from several of them at once (Gram slices, concurrent placement starts).
// With OpenBLAS's own threads, concurrent calls wait on its locks: the latent placement of 100
// materials took 161 s instead of 2.4 s.
//
// Only the routines matlas calls are bound. If the process had loaded OpenBLAS already (numpy in
// the same Python process, say), that library and its kernels are used as they are, and it too
// runs single-threaded from then on.
#include <cstddef>
#include <string>

#include <cblas.h>  // the CBLAS enums and declarations (nothing is linked against them)

namespace matlas::blas {

/// The routines of the loaded library.
struct Library {
  decltype(&cblas_dgemm) dgemm;
  decltype(&cblas_dsyrk) dsyrk;
  decltype(&cblas_ssyrk) ssyrk;
  decltype(&cblas_dsymm) dsymm;
  decltype(&cblas_dtrmm) dtrmm;
  decltype(&cblas_dtrsm) dtrsm;
  /// LAPACK's Cholesky factorisation (Fortran interface): uplo "L" or "U", n, a, lda, info.
  void (*dpotrf)(const char* uplo, const int* n, double* a, const int* lda, int* info);
  /// LAPACK's triangular inverse (uplo, diag "N" or "U", n, a, lda, info) and the product
  /// L^T L (or U U^T) of a triangle, in place (Fortran interface): LAPACK's dpotri is the two in
  /// turn (inverse_from_cholesky below).
  void (*dtrtri)(const char* uplo, const char* diag, const int* n, double* a, const int* lda, int* info);
  void (*dlauum)(const char* uplo, const int* n, double* a, const int* lda, int* info);
  /// LAPACK's symmetric eigen-decomposition by divide and conquer (Fortran interface): jobz "V"
  /// (vectors too) or "N", uplo, n, a, lda, w (eigenvalues, ascending), work, lwork, iwork,
  /// liwork, info; lwork = liwork = -1 asks for the workspace sizes (core/symmetric_eigen.h).
  void (*dsyevd)(const char* jobz, const char* uplo, const int* n, double* a, const int* lda, double* w,
                 double* work, const int* lwork, int* iwork, const int* liwork, int* info);
  decltype(&openblas_get_corename) corename;
  decltype(&openblas_get_config) config;
};

/// The offset of element (row, col) of a column-major matrix with leading dimension ld.
inline std::ptrdiff_t element(int row, int col, int ld) {
  return static_cast<std::ptrdiff_t>(row) + static_cast<std::ptrdiff_t>(col) * ld;
}

/// The library, loaded on the first call (thread-safe). Throws matlas::Error naming the library
/// and the loader's message when it cannot be loaded or lacks a routine.
const Library& openblas();

/// The lower triangle of `a` (n x n, leading dimension lda) replaced by its inverse, recursively
/// (the first half and the second inverted in turn and joined by two dtrmm, down to 16 columns);
/// returns LAPACK's info (0, or i > 0: a_ii is zero).
int invert_lower_triangle(int n, double* a, int lda);

/// K^-1 from the lower Cholesky factor L of K (n x n, column-major, leading dimension lda): the
/// lower triangle of `a` holds L on entry and the lower triangle of K^-1 on return (what LAPACK's
/// dpotri computes). The triangular inverse is recursive, halves inverted in turn and joined by
/// two triangular products (dtrmm), down to 16 columns: OpenBLAS's dtrtri inverts matrices of
/// up to 128 columns column by column with matrix-vector products, and at n = 100 that took 2.4x
/// longer (bench_optimizers BM_InverseFromCholesky). Returns LAPACK's info (0: success; i > 0: L_ii is zero).
int inverse_from_cholesky(int n, double* a, int lda);

/// The OpenBLAS kernel set ("SkylakeX", "Haswell") that matlas asks for on a processor with these
/// features, or "" to leave the choice to OpenBLAS. AVX-512 here means F, CD, BW, DQ and VL,
/// which the SkylakeX kernels use.
std::string kernel_for(bool avx512, bool avx2_fma);
/// kernel_for this processor's features.
std::string kernel_for_this_processor();

/// A note for the user (one sentence) when OPENBLAS_CORETYPE is set (`user_choice`, the variable's
/// value; null when unset) to other kernels than matlas would choose (`wanted`): the user's choice
/// wins, but it can cost half the speed (docs/BENCHMARKS.md, "OpenBLAS's kernels"). Empty when
/// unset, equal (in any case) or when matlas has no choice.
std::string kernel_override_note(const char* user_choice, const std::string& wanted);
/// The same for this process's environment and processor.
std::string kernel_override_note();

/// What runs, for reports: OpenBLAS's configuration string, e.g.
/// "OpenBLAS 0.3.21 NO_LAPACKE DYNAMIC_ARCH NO_AFFINITY SkylakeX MAX_THREADS=64".
std::string description();

}  // namespace matlas::blas
