#pragma once
// The baseline of sparse reconstruction: PCA of the database with directions chosen by the
// condition number (Nielsen, Jensen & Ramamoorthi 2015, "On Optimal, Minimal BRDF Sampling for
// Reflectance Acquisition"), in the same transformed space as matlas' fit (the layout's), so that
// the two differ in the prior only: a linear subspace with a Gaussian prior on its coefficients
// against the map.
//
// With the subset's transformed values t_i (centred on their mean t̄) at the rows that matter
// (sample rows, evaluation values), the principal components are u_k = sum_i a_ik (t_i - t̄)
// (a_k: eigenvectors of the subset's centred Gram over sqrt(lambda_k)), so they are evaluated at
// any row from the inputs' values there. A reconstruction from sample rows S solves the
// regularised least squares
//     b = argmin |U_S b - (y_S - t̄_S)|^2 + eta sum_k b_k^2 / (lambda_k / m)
// (the MAP estimate under the PCA's own Gaussian prior, lambda_k / m the variance of component k
// over the m inputs), and the reconstruction is t̄ + U b, mapped back to physical values.
#include <span>
#include <vector>

#include <Eigen/Core>

namespace matlas::eval {

/// The PCA of a subset of inputs in a transformed space.
struct SparsePca {
  Eigen::MatrixXd coefficients;  ///< m x k: a_k, the components as combinations of the centred inputs
  Eigen::VectorXd variance;      ///< k: lambda_k / m, the variance of each component's coefficient
  /// From the subset's centred Gram (m x m) in the transformed space; components with eigenvalue
  /// below 1e-10 of the largest are left out.
  static SparsePca fit(const Eigen::MatrixXd& centred_gram);
  /// The components at rows: T is rows x m transformed values of the subset's inputs (not
  /// centred); returns rows x k.
  Eigen::MatrixXd components(const Eigen::MatrixXd& T) const;
  /// Coefficients b from sample rows: U_S (rows x k, components at the rows), r = y - mean at
  /// the rows, eta the ridge.
  Eigen::VectorXd solve(const Eigen::MatrixXd& U_S, const Eigen::VectorXd& r, double eta) const;
};

/// Nielsen et al.'s greedy design: from the candidates (each `rows_per` consecutive rows of U,
/// the components at the candidates), adds one candidate at a time, the one that minimises the
/// condition number of the selected rows restricted to the first min(k, picks, max_components)
/// components. Returns `count` candidate indices in the order picked.
std::vector<int> condition_number_plan(const Eigen::MatrixXd& U, int rows_per, int count, int max_components);

}  // namespace matlas::eval
