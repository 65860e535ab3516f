#pragma once
// The one material-independent sampling density of a measured surface, shared by the previews
// (render/render.h) and the path tracer (pathtrace/tracer.h): a one-sample mixture of
// environment importance sampling (drawn by the caller, who owns the environment), the cosine
// lobe and GGX lobes of given widths around the mirror direction. It depends on nothing of the
// material being rendered, so every material of a basis sees the same directions and weights and
// images stay linear in the BRDF table. atlas/sampling_fit.h fits the lobes to a database.
#include <utility>
#include <vector>

#include "brdf/types.h"

namespace matlas::render {

struct SamplingMixture {
  SamplingMixture() = default;
  SamplingMixture(double environment_probability, double cosine_probability,
                  std::vector<std::pair<double, double>> ggx_lobes)
      : environment(environment_probability), cosine(cosine_probability), lobes(std::move(ggx_lobes)) {}

  double environment = 0.4;  ///< probability of drawing from the environment (0 for the path tracer)
  double cosine = 0.15;      ///< probability of the cosine lobe
  /// (alpha, probability) of the GGX lobes around the mirror direction. All probabilities are
  /// normalised by their sum (total()).
  std::vector<std::pair<double, double>> lobes = {{0.012, 0.15}, {0.06, 0.15}, {0.3, 0.15}};
  /// Probability of the tabulated half-vector lobe (set_profile): 0 until a profile is set.
  double tabulated = 0;

  /// The tabulated lobe: half vectors drawn per MERL theta_h bin (bin i covers theta_h in
  /// [(i/N)^2, ((i+1)/N)^2] * pi/2, the grid of measured tables, so a table's sharpest bins get
  /// a density that is constant over them) with probabilities proportional to `bin_weights`,
  /// uniformly in solid angle within a bin; wi is wo reflected about the half vector.
  void set_profile(std::vector<double> bin_weights, double probability);
  const std::vector<double>& profile() const { return profile_; }

  /// The previews' mixture before it was fitted to databases (the defaults above).
  static SamplingMixture preview_default() { return {}; }

  double total() const;
  /// Normalised probability of the environment strategy.
  double environment_probability() const { return environment / total(); }
  /// True when u (in [0, 1)) selects the environment strategy.
  bool picks_environment(double u) const { return u * total() < environment; }
  /// For u not selecting the environment: draws wi (local frame, normal +z) from the cosine lobe
  /// or the GGX lobe selected by u, with (u0, u1) for the direction.
  Vec3 sample_local(const Vec3& wo, double u, double u0, double u1) const;
  /// Density (per unit solid angle) of the cosine and GGX strategies, weighted by their
  /// normalised probabilities: add environment_probability() * env_pdf for the whole mixture.
  double local_pdf(const Vec3& wo, const Vec3& wi) const;

  /// The path tracer's form (environment = 0): draws wi with u0 picking the strategy, returns the
  /// mixture's density (0 when the draw fell below the horizon).
  double sample(const Vec3& wo, double u0, double u1, double u2, Vec3* wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const { return local_pdf(wo, wi); }

  /// Throws matlas::Error for negative or all-zero probabilities or alphas out of (0, 1].
  void validate() const;

private:
  std::vector<double> profile_;  ///< probability of each theta_h bin (sums to 1)
  std::vector<double> cdf_;      ///< running sums of profile_, size + 1
  std::vector<double> density_;  ///< profile_[i] / solid angle of bin i's half vectors
};

}  // namespace matlas::render
