#include "zonal/lobes.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/check.h"
#include "core/error.h"

namespace matlas::zonal {

double lobe_normalisation(double kappa) { return kappa / (2.0 * kPi * -std::expm1(-2.0 * kappa)); }

double lobe_value(double kappa, double t) { return lobe_normalisation(kappa) * std::exp(kappa * (t - 1.0)); }

std::vector<double> lobe_legendre(double kappa, int L) {
  // t = 1 - u / kappa: k_l = 2 pi N / kappa integral_0^{2 kappa} e^{-u} P_l(1 - u / kappa) du,
  // composite Simpson over u in [0, min(2 kappa, 60)] (e^{-60}: nothing left beyond).
  std::vector<double> k(static_cast<std::size_t>(L) + 1, 0.0);
  const double umax = std::min(2.0 * kappa, 60.0);
  const int steps = 2 * std::max(2000, 8 * (L + 1));  // even; several points per oscillation of P_L
  const double h = umax / steps, scale = 2.0 * kPi * lobe_normalisation(kappa) / kappa;
  for (int s = 0; s <= steps; ++s) {
    const double u = s * h, t = 1.0 - u / kappa;
    const double w = (s == 0 || s == steps ? 1.0 : (s % 2 ? 4.0 : 2.0)) * h / 3.0 * std::exp(-u) * scale;
    double p0 = 1.0, p1 = t;
    k[0] += w * p0;
    if (L >= 1) k[1] += w * p1;
    for (int l = 2; l <= L; ++l) {
      const double p2 = ((2.0 * l - 1.0) * t * p1 - (l - 1.0) * p0) / l;
      k[static_cast<std::size_t>(l)] += w * p2;
      p0 = p1;
      p1 = p2;
    }
  }
  return k;
}

double lobe_cosine_mass(double kappa, double rz) {
  // Over the circle r . w = t: w_z = a + b cos(phi), a = t rz, b = sqrt(1 - t^2) sqrt(1 - rz^2); the
  // mean of max(w_z, 0) over phi is (a phi0 + b sin phi0) / pi, phi0 = acos(-a / b) (a if b = 0).
  const double umax = std::min(2.0 * kappa, 60.0), q = std::sqrt(std::max(0.0, 1.0 - rz * rz));
  const int steps = 4000;
  const double h = umax / steps, scale = 2.0 * kPi * lobe_normalisation(kappa) / kappa;
  double sum = 0;
  for (int s = 0; s <= steps; ++s) {
    const double u = s * h, t = 1.0 - u / kappa;
    const double a = t * rz, b = std::sqrt(std::max(0.0, 1.0 - t * t)) * q;
    double mean;
    if (b <= 1e-300) mean = std::max(a, 0.0);
    else {
      const double phi0 = std::acos(std::clamp(-a / b, -1.0, 1.0));
      mean = (a * phi0 + b * std::sin(phi0)) / kPi;
    }
    sum += (s == 0 || s == steps ? 1.0 : (s % 2 ? 4.0 : 2.0)) * h / 3.0 * std::exp(-u) * mean;
  }
  return scale * sum;
}

double lobe_product(double a, double b) {
  return lobe_normalisation(a) * lobe_normalisation(b) * 2.0 * kPi * -std::expm1(-2.0 * (a + b)) / (a + b);
}

Eigen::VectorXd nonnegative_minimiser(const Eigen::MatrixXd& G, const Eigen::VectorXd& r) {
  const Eigen::Index M = r.size();
  MATLAS_CHECK(G.rows() == M && G.cols() == M && M <= 8, "a Gram matrix of the lobes' size, at most 8");
  Eigen::VectorXd c = G.ldlt().solve(r);
  if (M == 0 || c.minCoeff() >= 0.0) return c;
  // At a support's stationary point the objective is -1/2 c_S . r_S; c = 0 gives 0.
  c.setZero();
  double best = 0.0;
  std::vector<Eigen::Index> support;
  for (unsigned mask = 1; mask < (1u << M); ++mask) {
    support.clear();
    for (Eigen::Index i = 0; i < M; ++i)
      if (mask >> i & 1u) support.push_back(i);
    const auto n = static_cast<Eigen::Index>(support.size());
    Eigen::MatrixXd g(n, n);
    Eigen::VectorXd rs(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      rs(i) = r(support[static_cast<std::size_t>(i)]);
      for (Eigen::Index j = 0; j < n; ++j) g(i, j) = G(support[static_cast<std::size_t>(i)], support[static_cast<std::size_t>(j)]);
    }
    const Eigen::VectorXd cs = g.ldlt().solve(rs);
    if (cs.minCoeff() < 0.0) continue;
    const double objective = -0.5 * cs.dot(rs);
    if (objective < best) {
      best = objective;
      c.setZero();
      for (Eigen::Index i = 0; i < n; ++i) c(support[static_cast<std::size_t>(i)]) = cs(i);
    }
  }
  return c;
}

void validate_lobes(const std::vector<double>& kappas) {
  for (std::size_t i = 0; i < kappas.size(); ++i) {
    if (!(kappas[i] >= 1.0 && kappas[i] <= 65536.0))
      throw Error("lobe sharpness must be between 1 and 65536, got " + std::to_string(kappas[i]));
    if (i > 0 && !(kappas[i] > kappas[i - 1])) throw Error("lobe sharpnesses must be strictly increasing");
  }
  if (kappas.size() > 8) throw Error("at most 8 lobes, got " + std::to_string(kappas.size()));
}

}  // namespace matlas::zonal
