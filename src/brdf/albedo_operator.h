#pragma once
// Directional albedo as a linear functional of a table: a(theta_o) = sum over bins of
// f(bin) * A(bin, theta_o), from the same cosine-weighted quadrature as brdf/albedo.h with MERL's
// nearest-bin lookup. Because it is linear, it applies to column blocks of many tables at once
// (streaming builds) and commutes with the manifold's weighted sums.
#include <Eigen/SparseCore>

#include "brdf/merl_grid.h"

namespace matlas {

/// Sparse bins x angles matrix A (row-major): column t is the functional for theta_o at the
/// centre of bin t of `angles` uniform bins over [0, 90) degrees.
Eigen::SparseMatrix<double, Eigen::RowMajor> albedo_operator(const MerlDims& dims, int angles,
                                                             int resolution = 64);

}  // namespace matlas
