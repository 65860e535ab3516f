#pragma once
// Leave-one-out and baselines in Gram space.
//
// Every reconstruction matlas or a baseline makes is an affine combination of the input tables,
//     r = sum_i c_i z_i   with   sum_i c_i = 1
// ("raw coefficients" c; the GP's m(x) = mean + sum_i w_i (z_i - mean) is one with
// c = w + (1 - sum w) / n). With G any Gram matrix of the data centred on a common point (e.g. the
// centred Gram S of accumulate_gram), inner products of differences of tables are quadratic forms
// in G, so residuals of any such combination need no data pass: ||z_h - r||^2 = (e_h - c)^T G
// (e_h - c). Index sets ("subsets") list material indices into G.
#include <span>
#include <vector>

#include <Eigen/Core>

namespace matlas::eval {

/// Every index of 0..n-1 except `left_out` (or all of them when left_out < 0).
std::vector<int> indices_without(int n, int left_out);

/// Gram of the subset re-centred on its own mean: H G[T,T] H.
Eigen::MatrixXd centred_subset_gram(const Eigen::MatrixXd& gram, std::span<const int> subset);

/// (z_i - m_T) . (z_h - m_T) for i in the subset T (m_T: the subset's mean).
Eigen::VectorXd centred_cross_products(const Eigen::MatrixXd& gram, std::span<const int> subset,
                                       int h);

/// Raw coefficients (length n) of m_T + sum_k a_k (z_{T_k} - m_T), with a indexed like the subset.
Eigen::VectorXd raw_from_centred(const Eigen::VectorXd& a, std::span<const int> subset, int n);

/// Raw coefficients of the GP mean m(x) = mean + sum_k w_k (z_{T_k} - mean) over the subset.
inline Eigen::VectorXd raw_from_weights(const Eigen::VectorXd& w, std::span<const int> subset,
                                        int n) {
  return raw_from_centred(w, subset, n);
}

/// ||z_h - sum_i c_i z_i||^2 from the Gram (c must sum to 1).
double residual_squared(const Eigen::MatrixXd& gram, const Eigen::VectorXd& c, int h);

/// Squared distances between materials, ||z_i - z_j||^2, from the Gram.
Eigen::MatrixXd squared_distances_from_gram(const Eigen::MatrixXd& gram);

}  // namespace matlas::eval
