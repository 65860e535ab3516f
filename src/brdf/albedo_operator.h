#pragma once
// Directional albedo as a linear functional of a table: a(theta_o) = sum over bins of
// f(bin) * A(bin, theta_o), from the half-vector quadrature of brdf/albedo.h (albedo_rule: every
// theta_h bin integrated over its extent, MERL's nearest-bin lookup). Because it is linear, it
// applies to column blocks of many tables at once (streaming builds) and commutes with the
// manifold's weighted sums.
#include <Eigen/SparseCore>

#include "brdf/albedo.h"
#include "brdf/merl_grid.h"

namespace matlas {

/// Sparse bins x angles matrix A (row-major): column t is albedo_rule for theta_o at the centre
/// of bin t of `angles` uniform bins over [0, 90) degrees.
Eigen::SparseMatrix<double, Eigen::RowMajor> albedo_operator(const MerlDims& dims, int angles,
                                                             const AlbedoQuadrature& q = {});

}  // namespace matlas
