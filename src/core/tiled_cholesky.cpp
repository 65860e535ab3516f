#include "core/tiled_cholesky.h"

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/blas.h"
#include "core/check.h"
#include "core/parallel.h"
#include "core/tiled_products.h"

namespace matlas::blas {

namespace {

/// The tile grid of an n x n matrix: tile k spans [start(k), start(k) + size(k)).
struct Tiles {
  int n, tile, count;
  Tiles(int n_, int tile_) : n(n_), tile(tile_), count((n_ + tile_ - 1) / tile_) {}
  int start(int k) const { return k * tile; }
  int size(int k) const { return std::min(tile, n - k * tile); }
};

}  // namespace

int tiled_cholesky(int n, double* a, int lda, int tile) {
  MATLAS_CHECK(n >= 0 && tile > 0 && lda >= n);
  const Library& lib = openblas();
  int info = 0;
  if (n <= tile) {
    lib.dpotrf("L", &n, a, &lda, &info);
    return info;
  }
  const Tiles t(n, tile);
  for (int k = 0; k < t.count; ++k) {
    const int k0 = t.start(k), kb = t.size(k);
    double* akk = a + element(k0, k0, lda);
    lib.dpotrf("L", &kb, akk, &lda, &info);
    if (info != 0) return k0 + info;
    // The tiles below the diagonal one: A_ik L_kk^-T.
    parallel_for_each(0, static_cast<std::size_t>(t.count - k - 1), [&](std::size_t b) {
      const int i = k + 1 + static_cast<int>(b);
      lib.dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, t.size(i), kb, 1.0, akk, lda,
                a + element(t.start(i), k0, lda), lda);
    });
    // The trailing lower tiles: A_ij -= A_ik A_jk^T, the same tiles as this grid's.
    if (k + 1 < t.count) {
      const int k1 = t.start(k + 1);
      tiled_lower_gram(n - k1, kb, -1.0, a + element(k1, k0, lda), lda, 1.0, a + element(k1, k1, lda), lda, tile);
    }
  }
  return 0;
}

namespace {

/// invert_lower_triangle with its work on the workers, in fixed pieces: the two halves at once,
/// then C A^-1 by rows of C and D^-1 C by columns of C, `tile` at a time (rows of C times a lower
/// triangle from the right, and columns from the left, are independent).
int invert_lower_tiled(int n, double* a, int lda, int tile) {
  if (n <= tile) return invert_lower_triangle(n, a, lda);
  const Library& lib = openblas();
  const int h = n / 2, m = n - h;
  double* c = a + h;
  double* d = a + element(h, h, lda);
  int infos[2] = {0, 0};
  parallel_for_each(0, 2, [&](std::size_t half) {
    infos[half] = half == 0 ? invert_lower_tiled(h, a, lda, tile) : invert_lower_tiled(m, d, lda, tile);
  });
  if (infos[0] != 0) return infos[0];
  if (infos[1] != 0) return infos[1] + h;
  const Tiles rows(m, tile), cols(h, tile);
  parallel_for_each(0, static_cast<std::size_t>(rows.count), [&](std::size_t b) {
    const int r0 = rows.start(static_cast<int>(b));
    lib.dtrmm(CblasColMajor, CblasRight, CblasLower, CblasNoTrans, CblasNonUnit, rows.size(static_cast<int>(b)), h, 1.0,
              a, lda, c + r0, lda);
  });
  parallel_for_each(0, static_cast<std::size_t>(cols.count), [&](std::size_t b) {
    const int c0 = cols.start(static_cast<int>(b));
    lib.dtrmm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasNonUnit, m, cols.size(static_cast<int>(b)), -1.0,
              d, lda, c + element(0, c0, lda), lda);
  });
  return 0;
}

}  // namespace

int tiled_inverse_from_cholesky(int n, const double* l, int ldl, double* work, double* inverse, int ldi, int tile) {
  MATLAS_CHECK(n >= 0 && tile > 0 && ldl >= n && ldi >= n);
  if (n == 0) return 0;
  if (n <= tile) {
    for (int j = 0; j < n; ++j) std::copy(l + element(j, j, ldl), l + element(n, j, ldl), inverse + element(j, j, ldi));
    return inverse_from_cholesky(n, inverse, ldi);
  }
  // W = L^-1 in `work`, its strict upper triangle zero (the products below read whole tiles).
  for (int j = 0; j < n; ++j) {
    std::fill(work + element(0, j, n), work + element(j, j, n), 0.0);
    std::copy(l + element(j, j, ldl), l + element(n, j, ldl), work + element(j, j, n));
  }
  if (const int info = invert_lower_tiled(n, work, n, tile); info != 0) return info;
  // K^-1 = W^T W: tile (i, j), i >= j, is W[i0:, I]^T W[i0:, J] (W's rows above i0 are zero in I).
  const Tiles t(n, tile);
  std::vector<std::pair<int, int>> lower;
  for (int i = 0; i < t.count; ++i)
    for (int j = 0; j <= i; ++j) lower.emplace_back(i, j);
  const Library& lib = openblas();
  parallel_for_each(0, lower.size(), [&](std::size_t u) {
    const auto [i, j] = lower[u];
    const int i0 = t.start(i), rows = n - i0;
    lib.dgemm(CblasColMajor, CblasTrans, CblasNoTrans, t.size(i), t.size(j), rows, 1.0, work + element(i0, i0, n), n,
              work + element(i0, t.start(j), n), n, 0.0, inverse + element(i0, t.start(j), ldi), ldi);
  });
  return 0;
}

}  // namespace matlas::blas
