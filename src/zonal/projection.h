#pragma once
// Projection of a tabulated BRDF to rotated-ZH coefficients: lambda = M rho, linear in the table.
//
// For each theta_o sample the slice rho(wi) = f(wi, wo) cos theta_i (MERL's nearest-bin lookup,
// as the renderer evaluates tables; missing values read 0) is integrated against the even real
// harmonics on a midpoint grid of the upper hemisphere: `theta_rows` rows in theta_i and
// `phi_columns` columns over phi_i in [0, pi) (the slice is even in phi_i). The integral is
// separable: a cosine transform of each row (a matrix product), then the normalised associated
// Legendre functions per row. Band l's coefficients are then changed to the rotated-ZH basis
// (ZonalBasis::inverse). The bins read by every grid point are computed once per projector.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "brdf/brdf_table.h"
#include "zonal/basis.h"
#include "zonal/lobes.h"
#include "zonal/coefficients.h"
#include "zonal/ring_limit.h"

namespace matlas::zonal {

struct ProjectionSettings {
  int bands = 24;          ///< L
  int theta_o_count = 32;  ///< T
  int theta_rows = 128;    ///< quadrature rows in theta_i over [0, pi/2]
  int phi_columns = 256;   ///< quadrature columns in phi_i over [0, pi)
  /// Sharp lobes fitted beside the expansion (zonal/lobes.h; empty: none, the plain projection).
  std::vector<double> lobes = {};
  /// >= 0: after the projection every theta_o sample's bands are weighted by zonal::RingLimiter with
  /// this floor (zonal/ring_limit.h; the viewer's kRealtimeRingFloor); < 0: the plain truncation.
  double ring_floor = -1.0;
  /// Throws matlas::Error naming the setting out of range.
  void validate() const;
};

class ZonalProjector {
public:
  explicit ZonalProjector(const ProjectionSettings& settings, MerlDims dims = {});

  const ProjectionSettings& settings() const { return settings_; }
  const ZonalBasis& basis() const { return basis_; }
  /// The coefficients of a table (of this projector's grid size; matlas::Error otherwise).
  ZonalCoefficients project(const BrdfTable& table) const;
  /// Values of `count` tables at one bin and channel: gather(bin, channel, out) writes out[0..count)
  /// (missing values as 0). Called concurrently from several threads.
  using Gather = std::function<void(std::uint32_t bin, int channel, double* out)>;
  /// The coefficients of `count` tables at once, read through `gather` only at the bins the
  /// quadrature uses; the transforms are matrix products over all tables (blocked GEMM). Equal to
  /// project() of each table up to the order of the sums.
  std::vector<ZonalCoefficients> project_many(const Gather& gather, std::size_t count) const;

private:
  ProjectionSettings settings_;
  MerlDims dims_;
  ZonalBasis basis_;
  std::vector<std::uint32_t> bins_;  ///< [t][row][column]
  std::vector<double> cos_theta_;    ///< per row
  Eigen::MatrixXd cosines_;          ///< [column][m]: cos(m phi) * column width * 2 (both halves)
  Eigen::MatrixXd legendre_;         ///< [row][lm]: sqrt(2)^(m>0) Pbar_l^m(cos theta) (cos theta0 - cos theta1)
  /// Per theta_o sample, the lobe fit (zonal/lobes.h): c >= 0 minimising 1/2 c^T gram c - c^T (b -
  /// sum_lm a_lm spectra_lm), then a_lm -= sum_i c_i spectra(lm, i); stored c_i mass_i.
  struct LobeFit {
    Eigen::MatrixXd weights;  ///< [row * cols + col][i]: Kc_i(w) times the cell's area (both phi halves)
    Eigen::MatrixXd spectra;  ///< [lm][i]: the SH coefficients of Kc_i
    Eigen::MatrixXd gram;     ///< M x M: the high-pass Gram matrix (ridge-regularised)
    Eigen::VectorXd mass;     ///< integral of Kc_i over the sphere (lobe_cosine_mass)
  };
  std::vector<LobeFit> lobe_fits_;
  std::shared_ptr<const RingLimiter> ring_limiter_;  ///< with settings.ring_floor >= 0
  /// The quadrature's tables: cos_theta_, cosines_ and legendre_.
  void tabulate_quadrature();
  /// bins_: the MERL bin of every quadrature direction at every theta_o sample.
  void tabulate_bins();
  /// The lobe fit at theta_o sample t, from this projector's own quadrature.
  LobeFit lobe_fit(std::size_t t) const;
  /// Subtracts the fitted lobes from one table's SH coefficients a (triangle) at sample t, given the
  /// table's lobe inner products b; writes the lobe weights to c.
  void fit_lobes(std::size_t t, Eigen::VectorXd& a, const Eigen::VectorXd& b, double* c) const;
};

/// The slice reconstructed from coefficients: sum_{l,k} lambda_l^k(theta_o) Y_l^0(d_{l,k} . wi)
/// (+ sum_i c_i(theta_o) / mass_i K_i(r . wi) max(wi_z, 0) with lobes), wi in the local frame of the slice (wo in the
/// x-z plane, x >= 0). With `window` (w_0..w_L', zonal/window.h) band l is weighted by w_l and
/// bands above L' are left out.
Rgb reconstruct(const ZonalBasis& basis, const ZonalCoefficients& c, double theta_o, const Vec3& wi,
                const std::vector<double>* window = nullptr);

}  // namespace matlas::zonal
