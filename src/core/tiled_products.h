#pragma once
// Dense products through OpenBLAS (core/blas.h), cut into tiles of a fixed size that run on the
// worker threads. OpenBLAS runs single-threaded, so a large product on one thread leaves the other
// cores idle; the tiles are fixed by the shapes alone, never by the number of workers, so the
// result is the same to the bit on any machine and with any MATLAS_THREADS.
// Column-major, double, leading dimensions as BLAS's.

namespace matlas::blas {

/// C = alpha A B (A: m x k, B: k x n, C: m x n), in blocks of `block` columns of B and C.
void tiled_product(int m, int n, int k, double alpha, const double* a, int lda, const double* b, int ldb, double* c,
                   int ldc, int block = 128);

/// The lower triangle of C = alpha A A^T + beta C (A: n x k, C: n x n), in tiles of `tile` x
/// `tile` (dsyrk on the diagonal tiles, dgemm below them); C's strict upper triangle is not
/// touched.
void tiled_lower_gram(int n, int k, double alpha, const double* a, int lda, double beta, double* c, int ldc,
                      int tile = 192);

}  // namespace matlas::blas
