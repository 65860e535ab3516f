#pragma once
// The Cholesky factorisation of a symmetric positive definite matrix and the inverse from it, in
// tiles of a fixed size whose BLAS calls run on the worker threads (OpenBLAS itself runs
// single-threaded, core/blas.h). The tiles depend on the size alone, so the result is the same to
// the bit whatever the number of workers. A matrix of one tile takes LAPACK's dpotrf and
// blas::inverse_from_cholesky as they are. Column-major, double, lower triangles.

namespace matlas::blas {

/// K = L L^T in place: the lower triangle of `a` (n x n, leading dimension lda) holds K's on
/// entry and L on return (right-looking: each diagonal tile by dpotrf, the tiles below it by
/// dtrsm, the trailing tiles updated by dsyrk and dgemm); the strict upper triangle is not
/// touched. Returns LAPACK's info: 0, or i > 0 when the leading minor of order i is not positive
/// definite (the factor is then incomplete).
int tiled_cholesky(int n, double* a, int lda, int tile = 192);

/// The lower triangle of K^-1 into `inverse` (n x n, leading dimension ldi) from the lower
/// Cholesky factor L (n x n, leading dimension ldl; only its lower triangle is read), with `work`
/// (n x n, leading dimension n) as scratch: W = L^-1 by column blocks (dtrsm on the trailing
/// part of L), then K^-1 = W^T W by tiles (dgemm over the rows below each tile). The strict upper
/// triangle of `inverse` is left unspecified. Returns LAPACK's info (0, or i > 0: L_ii is zero).
int tiled_inverse_from_cholesky(int n, const double* l, int ldl, double* work, double* inverse, int ldi,
                                int tile = 192);

}  // namespace matlas::blas
