#include "gp_test_data.h"

#include <cmath>
#include <random>

namespace matlas::test {

namespace {

Eigen::MatrixXd normals(int rows, int cols, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = normal(rng);
  return m;
}

}  // namespace

Eigen::MatrixXd random_low_rank_data(int n, int D, int rank, std::uint64_t seed, double noise) {
  std::mt19937_64 rng(seed);
  const Eigen::MatrixXd A = normals(n, rank, rng);
  const Eigen::MatrixXd B = normals(rank, D, rng);
  return A * B + noise * normals(n, D, rng);
}

Eigen::MatrixXd curve_data(const Eigen::VectorXd& t, int D, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> omega(0.5, 1.5), phase(0.0, 6.283185307179586);
  Eigen::MatrixXd Z(t.size(), D);
  for (int c = 0; c < D; ++c) {
    const double w = omega(rng), p = phase(rng);
    for (Eigen::Index i = 0; i < t.size(); ++i) Z(i, c) = std::sin(w * t[i] + p);
  }
  return Z;
}

Eigen::MatrixXd centred_gram(const Eigen::MatrixXd& Z) {
  const Eigen::MatrixXd centred = Z.rowwise() - Z.colwise().mean();
  return centred * centred.transpose();
}

gp::LikelihoodProblem two_parameter_curves(int n) {
  const Eigen::MatrixXd T = random_points(n, 2, 41);
  Eigen::MatrixXd Z(n, 60);
  Z << curve_data(T.col(0), 30, 42), curve_data(T.col(1), 30, 43);
  gp::LikelihoodProblem p = problem_for(Z);
  p.prior = gp::LatentPrior::spread();
  return p;
}

gp::LikelihoodProblem problem_for(const Eigen::MatrixXd& Z, double columns) {
  gp::LikelihoodProblem p;
  p.gram = centred_gram(Z);
  p.columns = columns > 0 ? columns : static_cast<double>(Z.cols());
  return p;
}

Eigen::MatrixXd random_points(int n, int q, std::uint64_t seed, double scale) {
  std::mt19937_64 rng(seed);
  return scale * normals(n, q, rng);
}

}  // namespace matlas::test
