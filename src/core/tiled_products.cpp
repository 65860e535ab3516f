#include "core/tiled_products.h"

#include <algorithm>
#include <vector>

#include "core/blas.h"
#include "core/check.h"
#include "core/parallel.h"

namespace matlas::blas {

void tiled_product(int m, int n, int k, double alpha, const double* a, int lda, const double* b, int ldb, double* c,
                   int ldc, int block) {
  MATLAS_CHECK(m >= 0 && n >= 0 && k >= 0 && block > 0);
  if (m == 0 || n == 0) return;
  const Library& lib = openblas();
  const auto blocks = static_cast<std::size_t>((n + block - 1) / block);
  const auto one = [&](std::size_t j) {
    const int c0 = static_cast<int>(j) * block, width = std::min(block, n - c0);
    lib.dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, width, k, alpha, a, lda, b + element(0, c0, ldb), ldb,
              0.0, c + element(0, c0, ldc), ldc);
  };
  parallel_for_each(0, blocks, one);
}

void tiled_lower_gram(int n, int k, double alpha, const double* a, int lda, double beta, double* c, int ldc,
                      int tile) {
  MATLAS_CHECK(n >= 0 && k >= 0 && tile > 0);
  if (n == 0) return;
  const Library& lib = openblas();
  const int tiles = (n + tile - 1) / tile;
  struct Tile {
    int row, col;
  };
  std::vector<Tile> lower;  // the diagonal tiles last: the cheaper ones fill in at the end
  for (int i = 0; i < tiles; ++i)
    for (int j = 0; j < i; ++j) lower.push_back({i, j});
  for (int i = 0; i < tiles; ++i) lower.push_back({i, i});
  const auto one = [&](std::size_t t) {
    const Tile& at = lower[t];
    const int r0 = at.row * tile, rows = std::min(tile, n - r0);
    const int c0 = at.col * tile, cols = std::min(tile, n - c0);
    if (at.row == at.col)
      lib.dsyrk(CblasColMajor, CblasLower, CblasNoTrans, rows, k, alpha, a + r0, lda, beta, c + element(r0, r0, ldc), ldc);
    else
      lib.dgemm(CblasColMajor, CblasNoTrans, CblasTrans, rows, cols, k, alpha, a + r0, lda, a + c0, lda, beta,
                c + element(r0, c0, ldc), ldc);
  };
  parallel_for_each(0, lower.size(), one);
}

}  // namespace matlas::blas
