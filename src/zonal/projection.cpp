#include "zonal/projection.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "zonal/sh.h"

namespace matlas::zonal {

void ProjectionSettings::validate() const {
  if (bands < 0 || bands > 128) throw Error("zonal bands must be between 0 and 128, got " + std::to_string(bands));
  if (theta_o_count < 1 || theta_o_count > 1024)
    throw Error("theta_o samples must be between 1 and 1024, got " + std::to_string(theta_o_count));
  if (theta_rows < 4 || theta_rows > 4096 || phi_columns < 4 || phi_columns > 8192)
    throw Error("projection grid must be between 4x4 and 4096x8192, got " + std::to_string(theta_rows) + "x" +
                std::to_string(phi_columns));
  if (ring_floor >= 0.0) RingLimit{ring_floor}.validate();
}

ZonalProjector::ZonalProjector(const ProjectionSettings& settings, MerlDims dims)
    : settings_(settings), dims_(dims), basis_((settings.validate(), settings.bands)) {
  tabulate_quadrature();
  tabulate_bins();
  if (!settings.lobes.empty()) {
    validate_lobes(settings.lobes);
    lobe_fits_.resize(static_cast<std::size_t>(settings.theta_o_count));
    parallel_for_each(0, lobe_fits_.size(), [&](std::size_t t) { lobe_fits_[t] = lobe_fit(t); });
  }
  if (settings.ring_floor >= 0.0)
    ring_limiter_ = std::make_shared<const RingLimiter>(
        basis_, ZonalCoefficients{settings.bands, settings.theta_o_count, {}, settings.lobes}, RingLimit{settings.ring_floor});
}

void ZonalProjector::tabulate_quadrature() {
  const int L = settings_.bands, rows = settings_.theta_rows, cols = settings_.phi_columns;
  const double dtheta = (kPi / 2) / rows, dphi = kPi / cols;
  cos_theta_.resize(static_cast<std::size_t>(rows));
  cosines_.resize(cols, L + 1);
  for (int c = 0; c < cols; ++c)
    for (int m = 0; m <= L; ++m) cosines_(c, m) = std::cos(m * (c + 0.5) * dphi) * 2.0 * dphi;
  legendre_.resize(rows, static_cast<Eigen::Index>(triangle_size(L)));
  std::vector<double> p;
  for (int r = 0; r < rows; ++r) {
    const double theta = (r + 0.5) * dtheta;
    cos_theta_[static_cast<std::size_t>(r)] = std::cos(theta);
    normalized_legendre(L, std::cos(theta), p);
    const double row_weight = std::cos(theta - dtheta / 2) - std::cos(theta + dtheta / 2);  // exact band area
    for (int l = 0; l <= L; ++l)
      for (int m = 0; m <= l; ++m)
        legendre_(r, static_cast<Eigen::Index>(lm_index(l, m))) =
            (m > 0 ? std::sqrt(2.0) : 1.0) * p[lm_index(l, m)] * row_weight;
  }
}

void ZonalProjector::tabulate_bins() {
  const int rows = settings_.theta_rows, cols = settings_.phi_columns, T = settings_.theta_o_count;
  const double dtheta = (kPi / 2) / rows, dphi = kPi / cols;
  const std::size_t per_t = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  bins_.resize(per_t * static_cast<std::size_t>(T));
  parallel_for_each(0, static_cast<std::size_t>(T), [&](std::size_t t) {
    const double to = ZonalCoefficients::theta_o(static_cast<int>(t), T);
    const Vec3 wo(std::sin(to), 0.0, std::cos(to));
    for (int r = 0; r < rows; ++r) {
      const double theta = (r + 0.5) * dtheta;
      for (int c = 0; c < cols; ++c) {
        const double phi = (c + 0.5) * dphi;
        const Vec3 wi(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        bins_[t * per_t + static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c)] =
            static_cast<std::uint32_t>(bin_of(dims_, wi, wo));
      }
    }
  });
}

ZonalProjector::LobeFit ZonalProjector::lobe_fit(std::size_t t) const {
  const int L = settings_.bands, rows = settings_.theta_rows, cols = settings_.phi_columns, T = settings_.theta_o_count;
  const double dtheta = (kPi / 2) / rows, dphi = kPi / cols;
  const auto M = static_cast<Eigen::Index>(settings_.lobes.size());
  // The fitted functions are the cosine-weighted lobes Kc_i(w) = K_i(r . w) max(w_z, 0): zero
  // below the horizon and continuous across it, as the slice is. Their spectra and Gram matrix
  // (over the upper hemisphere) come from this projector's own quadrature.
  const double to = ZonalCoefficients::theta_o(static_cast<int>(t), T);
  const Vec3 r(-std::sin(to), 0.0, std::cos(to));
  LobeFit f;
  f.weights.resize(static_cast<Eigen::Index>(rows) * cols, M);
  std::vector<Eigen::MatrixXd> grid(static_cast<std::size_t>(M), Eigen::MatrixXd(rows, cols));
  for (int row = 0; row < rows; ++row) {
    const double theta = (row + 0.5) * dtheta;
    const double area = (std::cos(theta - dtheta / 2) - std::cos(theta + dtheta / 2)) * 2.0 * dphi;
    for (int c = 0; c < cols; ++c) {
      const double phi = (c + 0.5) * dphi;
      const double cosine = r.dot(Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
      for (Eigen::Index i = 0; i < M; ++i) {
        const double v = lobe_value(settings_.lobes[static_cast<std::size_t>(i)], cosine) * std::cos(theta);
        grid[static_cast<std::size_t>(i)](row, c) = v;
        f.weights(static_cast<Eigen::Index>(row) * cols + c, i) = area * v;
      }
    }
  }
  f.spectra.resize(static_cast<Eigen::Index>(triangle_size(L)), M);
  Eigen::MatrixXd gram(M, M);
  for (Eigen::Index i = 0; i < M; ++i) {
    const Eigen::MatrixXd fourier = grid[static_cast<std::size_t>(i)] * cosines_;  // as a slice's projection
    for (int l = 0; l <= L; ++l)
      for (int m = 0; m <= l; ++m)
        f.spectra(static_cast<Eigen::Index>(lm_index(l, m)), i) =
            fourier.col(m).dot(legendre_.col(static_cast<Eigen::Index>(lm_index(l, m))));
    for (Eigen::Index j = 0; j < M; ++j) {
      double sum = 0;  // weights' column i is area * Kc_i in row-major cell order
      for (int row = 0; row < rows; ++row)
        for (int c = 0; c < cols; ++c)
          sum += f.weights(static_cast<Eigen::Index>(row) * cols + c, i) * grid[static_cast<std::size_t>(j)](row, c);
      gram(i, j) = sum;
    }
  }
  // High-pass Gram matrix: <Kc_i, Kc_j> minus its bands 0..L; a small ridge (lobes far broader
  // than band L have almost no energy above it).
  gram -= f.spectra.transpose() * f.spectra;
  f.gram = gram + 1e-6 * gram.diagonal().maxCoeff() * Eigen::MatrixXd::Identity(M, M);
  // Stored weight: c_i times Kc_i's mass, so that shading is c_i mass_i E_i(r) (the environment
  // taken as even over the lobe).
  f.mass.resize(M);
  for (Eigen::Index i = 0; i < M; ++i) f.mass(i) = lobe_cosine_mass(settings_.lobes[static_cast<std::size_t>(i)], r.z());
  return f;
}

void ZonalProjector::fit_lobes(std::size_t t, Eigen::VectorXd& a, const Eigen::VectorXd& b, double* c) const {
  MATLAS_DCHECK_LT(t, lobe_fits_.size());
  const LobeFit& f = lobe_fits_[t];
  const Eigen::VectorXd weights = nonnegative_minimiser(f.gram, b - f.spectra.transpose() * a);
  a -= f.spectra * weights;
  for (Eigen::Index i = 0; i < weights.size(); ++i) c[i] = weights(i) * f.mass(i);
}

ZonalCoefficients ZonalProjector::project(const BrdfTable& table) const {
  if (!(table.dims() == dims_))
    throw Error("zonal projection: table of size " + table.dims().to_string() + ", projector for " + dims_.to_string());
  const int L = settings_.bands, rows = settings_.theta_rows, cols = settings_.phi_columns, T = settings_.theta_o_count;
  ZonalCoefficients out;
  out.bands = L;
  out.theta_o_count = T;
  out.lobes = settings_.lobes;
  const std::size_t S = out.size(), K = out.zonal_size();
  out.values.assign(static_cast<std::size_t>(T) * S * 3, 0.0);
  const std::size_t per_t = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  parallel_for_each(0, static_cast<std::size_t>(T), [&](std::size_t t) {
    // rho per channel as a rows x cols matrix (row-major: one theta_i row after the other).
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rho[3];
    for (auto& m : rho) m.resize(rows, cols);
    const std::uint32_t* bins = &bins_[t * per_t];
    for (int r = 0; r < rows; ++r) {
      const double ct = cos_theta_[static_cast<std::size_t>(r)];
      for (int c = 0; c < cols; ++c) {
        const Rgb f = table.bin_rgb(bins[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) +
                                         static_cast<std::size_t>(c)]);
        for (int ch = 0; ch < 3; ++ch) rho[ch](r, c) = f[ch] * ct;
      }
    }
    Eigen::VectorXd a(static_cast<Eigen::Index>(K)), c(static_cast<Eigen::Index>(settings_.lobes.size()));
    for (int ch = 0; ch < 3; ++ch) {
      const Eigen::MatrixXd fourier = rho[ch] * cosines_;  // rows x (L+1)
      for (int l = 0; l <= L; ++l)
        for (int m = 0; m <= l; ++m)
          a(static_cast<Eigen::Index>(lm_index(l, m))) =
              fourier.col(m).dot(legendre_.col(static_cast<Eigen::Index>(lm_index(l, m))));
      if (!lobe_fits_.empty()) {
        const Eigen::Map<const Eigen::VectorXd> flat(rho[ch].data(), rho[ch].size());
        const Eigen::VectorXd b = lobe_fits_[t].weights.transpose() * flat;
        fit_lobes(t, a, b, c.data());
        for (Eigen::Index i = 0; i < c.size(); ++i)
          out.values[(t * S + K + static_cast<std::size_t>(i)) * 3 + static_cast<std::size_t>(ch)] = c(i);
      }
      for (int l = 0; l <= L; ++l) {
        const Eigen::VectorXd lambda = basis_.inverse(l) * a.segment(static_cast<Eigen::Index>(lm_index(l, 0)), l + 1);
        for (int k = 0; k <= l; ++k)
          out.values[(t * S + lm_index(l, k)) * 3 + static_cast<std::size_t>(ch)] = lambda(k);
      }
    }
  });
  if (ring_limiter_) ring_limiter_->apply(out);
  return out;
}

std::vector<ZonalCoefficients> ZonalProjector::project_many(const Gather& gather, std::size_t count) const {
  const int L = settings_.bands, rows = settings_.theta_rows, cols = settings_.phi_columns, T = settings_.theta_o_count;
  std::vector<ZonalCoefficients> out(count);
  const std::size_t K = triangle_size(L), M = settings_.lobes.size(), S = K + M;
  for (ZonalCoefficients& c : out) {
    c.bands = L;
    c.theta_o_count = T;
    c.lobes = settings_.lobes;
    c.values.assign(static_cast<std::size_t>(T) * S * 3, 0.0);
  }
  if (count == 0) return out;
  const auto n = static_cast<Eigen::Index>(count);
  const std::size_t per_t = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  parallel_for_each(0, static_cast<std::size_t>(T) * 3, [&](std::size_t task) {
    const std::size_t t = task / 3;
    const int ch = static_cast<int>(task % 3);
    // rho of every table: row (r, i) = theta_i row r of table i, columns phi_i.
    Eigen::MatrixXd rho(static_cast<Eigen::Index>(rows) * n, cols);
    std::vector<double> values(count);
    const std::uint32_t* bins = &bins_[t * per_t];
    for (int r = 0; r < rows; ++r) {
      const double ct = cos_theta_[static_cast<std::size_t>(r)];
      for (int c = 0; c < cols; ++c) {
        gather(bins[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c)], ch,
               values.data());
        for (Eigen::Index i = 0; i < n; ++i) rho(r * n + i, c) = values[static_cast<std::size_t>(i)] * ct;
      }
    }
    const Eigen::MatrixXd fourier = rho * cosines_;  // (rows n) x (L+1)
    Eigen::MatrixXd by_row(rows, n);
    for (int m = 0; m <= L; ++m) {
      for (int r = 0; r < rows; ++r) by_row.row(r) = fourier.col(m).segment(r * n, n).transpose();
      // a_lm of every table for l = m..L: Legendre weights (rows) against the rows' Fourier terms.
      for (int l = m; l <= L; ++l) {
        const Eigen::RowVectorXd a = legendre_.col(static_cast<Eigen::Index>(lm_index(l, m))).transpose() * by_row;
        for (Eigen::Index i = 0; i < n; ++i)
          out[static_cast<std::size_t>(i)].values[(t * S + lm_index(l, m)) * 3 + static_cast<std::size_t>(ch)] = a(i);
      }
    }
    // Lobe inner products of every table: b (n x M) = sum over rows of rho's block times the weights.
    Eigen::MatrixXd b;
    if (!lobe_fits_.empty()) {
      const Eigen::MatrixXd& w = lobe_fits_[t].weights;
      b = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(M));
      for (int r = 0; r < rows; ++r)
        b.noalias() += rho.middleRows(static_cast<Eigen::Index>(r) * n, n) *
                       w.middleRows(static_cast<Eigen::Index>(r) * cols, cols);
    }
    // SH coefficients a_l -> (lobes fitted and subtracted) rotated-ZH lambda_l, in place per band.
    Eigen::VectorXd a(static_cast<Eigen::Index>(K));
    std::vector<double> weights(M);
    for (std::size_t i = 0; i < count; ++i) {
      ZonalCoefficients& c = out[i];
      for (std::size_t j = 0; j < K; ++j) a(static_cast<Eigen::Index>(j)) = c.values[(t * S + j) * 3 + static_cast<std::size_t>(ch)];
      if (!lobe_fits_.empty()) {
        fit_lobes(t, a, b.row(static_cast<Eigen::Index>(i)).transpose(), weights.data());
        for (std::size_t k = 0; k < M; ++k) c.values[(t * S + K + k) * 3 + static_cast<std::size_t>(ch)] = weights[k];
      }
      for (int l = 0; l <= L; ++l) {
        const Eigen::VectorXd lambda = basis_.inverse(l) * a.segment(static_cast<Eigen::Index>(lm_index(l, 0)), l + 1);
        for (int k = 0; k <= l; ++k) c.values[(t * S + lm_index(l, k)) * 3 + static_cast<std::size_t>(ch)] = lambda(k);
      }
    }
  });
  if (ring_limiter_) parallel_for_each(0, count, [&](std::size_t i) { ring_limiter_->apply(out[i]); });
  return out;
}

Rgb reconstruct(const ZonalBasis& basis, const ZonalCoefficients& c, double theta_o, const Vec3& wi,
                const std::vector<double>* window) {
  if (c.bands > basis.bands()) throw Error("zonal reconstruction: coefficients have more bands than the basis");
  std::vector<double> lambda, y;
  c.interpolate(theta_o, lambda);
  Rgb sum = Rgb::Zero();
  const std::size_t K = c.zonal_size();
  for (std::size_t j = 0; j < K; ++j) {
    const int l = basis.band(j);
    if (window && static_cast<std::size_t>(l) >= window->size()) break;
    zonal_harmonics(l, basis.direction(j).dot(wi), y);
    const double w = window ? (*window)[static_cast<std::size_t>(l)] : 1.0;
    sum += w * y[static_cast<std::size_t>(l)] * Rgb(lambda[3 * j], lambda[3 * j + 1], lambda[3 * j + 2]);
  }
  const Vec3 r(-std::sin(theta_o), 0.0, std::cos(theta_o));
  for (std::size_t i = 0; i < c.lobes.size(); ++i) {
    const std::size_t j = K + i;
    const double mass = lobe_cosine_mass(c.lobes[i], r.z());
    sum += lobe_value(c.lobes[i], r.dot(wi)) * std::max(wi.z(), 0.0) / mass *
           Rgb(lambda[3 * j], lambda[3 * j + 1], lambda[3 * j + 2]);
  }
  return sum;
}

}  // namespace matlas::zonal
