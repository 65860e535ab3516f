#include "acquisition/sample_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/check.h"
#include "core/error.h"

namespace matlas::acquisition {

PlanCandidates plan_candidates(const MerlDims& dims, int theta_h_step, int theta_d_step, int phi_d_step) {
  if (theta_h_step < 0 || theta_d_step < 0 || phi_d_step < 0) throw Error("plan candidates: steps must be >= 0");
  if (theta_h_step == 0) theta_h_step = std::max(1, dims.theta_h / 30);
  if (theta_d_step == 0) theta_d_step = std::max(1, dims.theta_d / 18);
  if (phi_d_step == 0) phi_d_step = std::max(1, dims.phi_d / 18);
  const double cos80 = std::cos(80.0 * 3.14159265358979323846 / 180.0);
  PlanCandidates out;
  for (int i = 0; i < dims.theta_h; i += theta_h_step)
    for (int j = 0; j < dims.theta_d; j += theta_d_step)
      for (int k = 0; k < dims.phi_d; k += phi_d_step) {
        const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
        if (d.wi.z() <= cos80 || d.wo.z() <= cos80) continue;
        MeasuredSample s;
        s.wi = d.wi;
        s.wo = d.wo;
        s.line = static_cast<int>(out.directions.size()) + 1;
        out.directions.push_back(s);
        out.bins.push_back(dims.flat(i, j, k));
      }
  return out;
}

namespace {

/// Rows of `values` (physical, rows 3c + channel) in the transform's space.
Eigen::MatrixXd transformed_rows(const Eigen::MatrixXd& values, const Eigen::VectorXd& row_cosine,
                                 const LayoutTransform& transform) {
  MATLAS_CHECK_EQ(row_cosine.size(), values.rows());
  Eigen::MatrixXd t(values.rows(), values.cols());
  for (Eigen::Index i = 0; i < values.cols(); ++i)
    for (Eigen::Index r = 0; r < values.rows(); ++r) t(r, i) = transform_value(transform, values(r, i), row_cosine(r));
  return t;
}

}  // namespace

Plan plan_directions(const PlanSpace& space, const Eigen::VectorXd& material_weight, const SampleRows* measured,
                     int count, const PlanOptions& options, std::span<const int> excluded) {
  const Eigen::Index C = space.cosine.size(), n = space.values.cols();
  if (space.values.rows() != 3 * C) throw Error("sample plan: candidate values and cosines disagree");
  if (material_weight.size() != n || (material_weight.array() < 0).any() || !(material_weight.sum() > 0))
    throw Error("sample plan: need " + std::to_string(n) + " non-negative input weights, not all zero");
  if (count < 1) throw Error("sample plan: the count must be at least 1");
  if (measured && measured->inputs.rows() > 0 && measured->inputs.cols() != n)
    throw Error("sample plan: the measured rows do not match the inputs");
  count = static_cast<int>(std::min<Eigen::Index>(count, C));

  const Eigen::VectorXd p = material_weight / material_weight.sum();
  const Eigen::VectorXd sqrt_p = p.cwiseSqrt();
  Eigen::VectorXd row_cosine(3 * C);
  for (Eigen::Index c = 0; c < C; ++c) row_cosine.segment(3 * c, 3).setConstant(space.cosine(c));
  // Weighted, centred inputs at the candidates, and their leading components G = G0 V_r.
  Eigen::MatrixXd G0 = transformed_rows(space.values, row_cosine, options.transform);
  // Measurement noise grows with each row's magnitude (a device's error is partly a share of what
  // it reads): sigma_r = noise x sqrt(rms_r x typical), rms_r the row's RMS over the inputs and
  // typical the RMS of all rows, so a row 100x brighter than typical is 10x noisier. Rows are
  // whitened by it: bright rows (specular peaks, where the inputs differ most in absolute terms)
  // no longer take every pick from dim rows that tell the materials apart as well, and dim rows
  // (grazing, dark) do not take them all either.
  auto row_rms = [&](const Eigen::MatrixXd& T) { return Eigen::VectorXd((T.array().square().matrix() * p).cwiseSqrt()); };
  const Eigen::VectorXd rms = row_rms(G0);
  const double typical = std::max(std::sqrt(rms.squaredNorm() / static_cast<double>(rms.size())), 1e-300);
  auto row_noise = [&](const Eigen::MatrixXd& T) {
    return Eigen::VectorXd(options.noise * (row_rms(T).cwiseMax(1e-3 * typical) * typical).cwiseSqrt());
  };
  const Eigen::VectorXd sigma = row_noise(G0);
  const Eigen::VectorXd mu = G0 * p;
  G0 = (G0.colwise() - mu) * sqrt_p.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(G0.transpose() * G0);
  const Eigen::VectorXd lambda = eigen.eigenvalues();  // ascending
  const double top = std::max(lambda.maxCoeff(), 1e-300);
  Eigen::Index r = 0;
  while (r < std::min<Eigen::Index>(options.rank, n) && lambda(n - 1 - r) > 1e-10 * top) ++r;
  r = std::max<Eigen::Index>(r, 1);
  const Eigen::MatrixXd V = eigen.eigenvectors().rightCols(r);
  const Eigen::MatrixXd G_raw = G0 * V;  // 3C x r; the prior of a is N(0, I)
  const Eigen::MatrixXd G = sigma.cwiseInverse().asDiagonal() * G_raw;  // whitened: unit noise
  const double total = G_raw.squaredNorm();
  const double sigma2 = 1.0;

  // The posterior of a in information form, Lambda = I + sum of H^T H / sigma^2 over the observed
  // rows H, and P = Lambda^-1 from its Cholesky factor (Lambda >= I: well conditioned; the
  // covariance form's Woodbury downdates lose definiteness once the rows outnumber r).
  Eigen::MatrixXd information = Eigen::MatrixXd::Identity(r, r);
  Eigen::MatrixXd P = information;
  auto condition = [&](const Eigen::MatrixXd& rows) {  // rows: k x r observed with noise sigma2
    information.noalias() += rows.transpose() * rows / sigma2;
    P = information.llt().solve(Eigen::MatrixXd::Identity(r, r));
    P = 0.5 * (P + P.transpose());
  };
  if (measured && measured->rows() > 0) {
    Eigen::MatrixXd M = transformed_rows(measured->inputs, measured->cosine, options.transform);
    const Eigen::VectorXd mu_m = M * p;
    const Eigen::VectorXd sigma_m = row_noise(M);
    M = sigma_m.cwiseInverse().asDiagonal() * (((M.colwise() - mu_m) * sqrt_p.asDiagonal()) * V);
    condition(M);
  }
  const Eigen::MatrixXd GtG = G_raw.transpose() * G_raw;
  Plan plan;
  std::vector<bool> taken(static_cast<std::size_t>(C), false);
  for (int c : excluded)
    if (c >= 0 && c < C) taken[static_cast<std::size_t>(c)] = true;
  for (int step = 0; step < count; ++step) {
    const Eigen::MatrixXd H = G * P;  // 3C x r
    double best_gain = -1;
    Eigen::Index best = -1;
    for (Eigen::Index c = 0; c < C; ++c) {
      if (taken[static_cast<std::size_t>(c)]) continue;
      Eigen::Matrix3d A = G.middleRows(3 * c, 3) * H.middleRows(3 * c, 3).transpose() / sigma2;
      A.diagonal().array() += 1.0;
      const double gain = std::log(std::max(A.determinant(), 1.0));  // A >= I
      if (gain > best_gain) best_gain = gain, best = c;
    }
    if (best < 0) break;
    taken[static_cast<std::size_t>(best)] = true;
    condition(G.middleRows(3 * best, 3));
    plan.chosen.push_back(static_cast<int>(best));
    plan.gain.push_back(best_gain);
    plan.remaining.push_back(total > 0 ? (P * GtG).trace() / total : 0.0);
  }
  return plan;
}

Eigen::VectorXd plausible_inputs(const Eigen::VectorXd& input_loss, double effective) {
  const Eigen::Index n = input_loss.size();
  if (n == 0) return {};
  effective = std::clamp(effective, 1.0, static_cast<double>(n));
  const Eigen::ArrayXd excess = input_loss.array() - input_loss.minCoeff();
  auto weights = [&](double T) { return Eigen::ArrayXd((-excess / T).exp()); };
  auto ess = [&](double T) {
    const Eigen::ArrayXd w = weights(T);
    return w.sum() * w.sum() / w.square().sum();
  };
  // ess grows with T from the number of ties at the minimum to n: bisect on log T.
  double lo = 1e-12, hi = 1e12;
  if (ess(hi) <= effective) return Eigen::VectorXd(weights(hi).matrix());
  if (ess(lo) >= effective) return Eigen::VectorXd(weights(lo).matrix());
  for (int it = 0; it < 200 && hi / lo > 1 + 1e-6; ++it) {
    const double mid = std::sqrt(lo * hi);
    (ess(mid) < effective ? lo : hi) = mid;
  }
  return Eigen::VectorXd(weights(hi).matrix());
}

}  // namespace matlas::acquisition
