#pragma once
// The repulsive prior over the pairs of latent points within its cutoff, for the sparse latent
// optimisation (sparse_likelihood.h): O(n log n + pairs) where the dense likelihood's is O(n^2).
#include <Eigen/Core>

namespace matlas::gp {

/// The repulsive prior lambda sum_{i<j, u_ij < 40} log(1 - e^{-u_ij} + 1e-12), u_ij =
/// |x_i - x_j|^2 / rho^2, over the pairs within the cutoff only (O(n log n + pairs in the slab)),
/// and (optionally) adds its gradient to *gradient (n x q). Returns the value (0 when repulsion is 0).
/// The points are sorted by their first coordinate and each is paired with the following ones
/// while they are within the cutoff in that coordinate, in fixed ranges of the sorted points run
/// on the worker threads and added in order: the result does not depend on the thread count.
double sparse_repulsion(const Eigen::MatrixXd& X, double repulsion, double radius, Eigen::MatrixXd* gradient);

}  // namespace matlas::gp
