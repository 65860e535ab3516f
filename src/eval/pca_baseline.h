#pragma once
// The PCA baseline in Gram space: mean plus q principal components fitted on a subset of the
// materials, with the components expressed as combinations of the subset's tables (the dual /
// "snapshot" form of PCA: eigenvectors of the subset's centred Gram).
#include <span>

#include <Eigen/Core>

namespace matlas::eval {

/// Raw coefficients (length n, summing to 1) of the PCA reconstruction of material h from
/// `components` principal components fitted on `subset` (h need not be outside the subset):
///     r = m_T + sum_k <z_h - m_T, u_k> u_k.
/// Components with a negligible eigenvalue (below 1e-12 of the largest) are left out. gram is any
/// Gram matrix of all n materials centred on a common point.
Eigen::VectorXd pca_reconstruction(const Eigen::MatrixXd& gram, std::span<const int> subset, int h,
                                   int components);

}  // namespace matlas::eval
