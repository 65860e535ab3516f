#pragma once
// The microfacet normal distribution of a tabulated BRDF, by the power iterations of Dupuy,
// Hill, Heitz and Iehl 2015 ("Extracting microfacet-based BRDF parameters from arbitrary
// materials with power iterations"), isotropic case.
//
// In the back-scattering direction k (light and view both along k, so the half vector is k) a
// microfacet BRDF with Smith shadowing is f(k, k) = F D(k) / (4 cos(theta_k) sigma(k)), where
// sigma(k) = integral of D(m) max(0, k.m) dm is the projected area of the microsurface seen
// from k. So D is proportional to f(k, k) cos(theta_k) sigma(k), a fixed point reached by
//   D_{n+1}(k) = f(k, k) cos(theta_k) sigma_n(k),  normalised to integral D(m) cos(theta_m) dm = 1
// (then sigma(normal) = 1), starting from sigma_0 = 1. The back-scattering f(k, k) is read from
// the table's first theta_d bins (theta_d under 3 deg, the nearest MERL measures to exact
// retro-reflection), averaged over phi_d, as luminance. The result includes every part of the
// reflection that back-scatters (a diffuse floor too), which is what a renderer's sampling wants.
//
// D is tabulated at nodes u_k = k / (n - 1) of MERL's and RGL's square-root coordinate
// u = sqrt(2 theta / pi), linear in u between them; sigma is integrated exactly in azimuth
// (closed form of the integral of max(0, a + b cos phi)) and by a midpoint rule in u.
#include <vector>

#include "brdf/brdf_table.h"

namespace matlas {

struct NdfExtractionOptions {
  int nodes = 181;       ///< D's nodes in u (181: two per MERL theta_h bin)
  int iterations = 12;   ///< power iterations (Dupuy et al. report convergence within a few)
  /// Smallest D relative to its peak: back-scattering that is zero or unmeasured would make the
  /// VNDF zero over whole regions, which no sampling warp can hold.
  double floor = 1e-6;
};

class MicrofacetNdf {
public:
  MicrofacetNdf() = default;
  /// From values at the nodes u_k = k / (n - 1), n >= 2, all finite and >= 0, not all 0;
  /// normalised here so that integral D cos(theta_m) dm = 1.
  explicit MicrofacetNdf(std::vector<double> node_values);

  const std::vector<double>& nodes() const { return d_; }
  /// D at the unit coordinate u = sqrt(2 theta / pi) in [0, 1] (clamped), linear between nodes.
  double at_unit(double u) const;
  /// D at the polar angle theta of the microfacet normal (1/sr).
  double operator()(double theta) const;
  /// sigma(theta_i) = integral D(m) max(0, wi.m) dm for wi at elevation theta_i.
  double projected_area(double theta_i) const;
  /// integral D(m) cos(theta_m) dm (1 after normalisation).
  double normalisation() const { return projected_area(0.0); }

private:
  std::vector<double> d_;
};

struct NdfExtractionReport {
  int iterations = 0;
  /// Largest relative change of D at a node in the last iteration (the convergence measure).
  double last_change = 0;
};

/// D by power iterations on the table's back-scattering (see above). Missing back-scattering
/// bins take their nearest measured neighbour's value; a table with no back-scattering at all
/// (all zero) gets a uniform D (the cosine-weighted hemisphere).
MicrofacetNdf extract_ndf(const BrdfTable& table, const NdfExtractionOptions& options = {},
                          NdfExtractionReport* report = nullptr);

/// D from back-scattering values f(k, k) at the nodes u_k = k / (n - 1) (the iterations alone).
MicrofacetNdf ndf_from_backscattering(const std::vector<double>& backscattering, const NdfExtractionOptions& options = {},
                                      NdfExtractionReport* report = nullptr);

}  // namespace matlas
