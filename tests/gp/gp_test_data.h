#pragma once
// Synthetic data for the gp tests: random low-rank data, smooth curves of a scalar parameter, and
// their centred Gram matrices. Deterministic for a given seed.
#include <Eigen/Core>
#include <cstdint>

#include "gp/likelihood.h"

namespace matlas::test {

/// n x D data of the given rank: (n x rank standard normals) * (rank x D standard normals) plus a
/// little isotropic noise so that the Gram has full rank n-1 after centring.
Eigen::MatrixXd random_low_rank_data(int n, int D, int rank, std::uint64_t seed, double noise = 0.05);

/// Rows Z_i(c) = sin(omega_c t_i + phi_c) (smooth functions of the scalar t_i), D columns.
Eigen::MatrixXd curve_data(const Eigen::VectorXd& t, int D, std::uint64_t seed);

/// A problem whose layout is well determined: n points of a 2-D parameter (standard normal,
/// seed 41), data = 30 smooth curves of each coordinate (seeds 42, 43), the build's spread prior.
gp::LikelihoodProblem two_parameter_curves(int n);

/// S = (Z - mean)(Z - mean)^T.
Eigen::MatrixXd centred_gram(const Eigen::MatrixXd& Z);

/// A likelihood problem for data Z (columns = Z.cols() unless given).
gp::LikelihoodProblem problem_for(const Eigen::MatrixXd& Z, double columns = 0);

/// n x q standard normal points.
Eigen::MatrixXd random_points(int n, int q, std::uint64_t seed, double scale = 1.0);

}  // namespace matlas::test
