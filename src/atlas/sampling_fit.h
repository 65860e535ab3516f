#pragma once
// The sampling mixture of a database's renders (render/sampling_mixture.h), fitted to the
// database and not to the material being rendered: every material of a basis keeps the same
// density, so images stay linear in the table.
//
// Fit. Each material's specular lobe is read from its luminance along theta_h (theta_d = 10
// degrees, phi_d = 90 degrees, MERL bin centres, theta_h up to 70 degrees): the lobe is the part
// above the floor (the smallest value), and materials whose peak is under twice the floor have
// none. Its energy per theta_h bin, (f - floor) cos(theta_h) times the bin's solid angle of half
// vectors, normalised per material, gives
//  - the tabulated lobe (SamplingMixture::set_profile): per bin the LARGEST share over the
//    database's materials, so that every material's lobe is covered within a bounded factor
//    (an average would dilute chrome's few sharp bins among the rough materials);
//  - GGX widths: a GGX lobe of width alpha sampled by D cos puts the fraction
//    tan^2 / (alpha^2 + tan^2) below theta_h, so the energy's quartiles and median give three
//    estimates of alpha (the median one is the material's width); the mixture's GGX lobes sit
//    at the 10th, 50th and 90th percentiles of the pooled log-widths (merged when within a
//    factor 1.5), sharing `lobe_share`, and one at the sharpest material's width
//    (`sharpest_share`).
// Environment and cosine keep their probabilities. The shares were chosen per sampler on 83
// measured materials (docs/RENDERING.md "Noise"): the default light-and-lobe sampler takes an
// environment sample besides every lobe sample, so its lobes can favour the sharp end
// (SamplingFitOptions::for_sampler).
#include <vector>

#include "manifold/model.h"
#include "render/material.h"
#include "render/render.h"
#include "render/sampling_mixture.h"

namespace matlas::atlas {

struct SamplingFitOptions {
  double environment = 0.5;
  double cosine = 0.05;
  double lobe_share = 0.1;
  /// A GGX lobe at the sharpest material's width (the smallest median width of the database):
  /// chrome-like lobes and clear-coat spikes, where the tabulated lobe (its per-bin maximum shares
  /// summed over the database's bins) puts a small fraction of its samples.
  double sharpest_share = 0.2;
  double tabulated = 0.15;  ///< the database's lobes per theta_h bin (set_profile)
  std::vector<double> quantiles = {0.1, 0.5, 0.9};
  double min_alpha = 0.001, max_alpha = 0.5;

  /// The shares chosen for a sampler: the defaults above for the stratified (and independent)
  /// sampler; for light_and_lobe, whose environment samples serve the wide lobes, cosine 0.1,
  /// the sharpest lobe 0.45 and the tabulated lobe 0.1 (of the lobe strategies' total 0.75: the
  /// environment's probability is not used by that sampler).
  static SamplingFitOptions for_sampler(render::Sampler sampler);
};

/// Width (GGX alpha) of each material's specular lobe, 0 for materials without one.
std::vector<double> specular_lobe_widths(const render::MaterialBank& bank);

/// The mixture fitted to a bank's materials; with no glossy material, the default mixture.
render::SamplingMixture fit_sampling_mixture(const render::MaterialBank& bank, const SamplingFitOptions& options = {});
/// The mixture fitted to a model's database materials (its ModelBank without the mean).
render::SamplingMixture fit_sampling_mixture(const Model& model, const SamplingFitOptions& options = {});

/// The defensive mixture of two (Hesterberg 1995): each strategy of `a` and of `b` with half its
/// normalised probability, the tabulated lobes merged into one profile (the same per-bin form, so
/// the merge is exact), so that its density is (a's + b's) / 2 for any direction. A one-sample
/// estimator with it has at most twice the variance of the better of the two, whichever that is:
/// what a refined preview uses for one material, from the mixture fitted to that material and
/// the database's (neither is better for every material: docs/RENDERING.md "Refinement").
render::SamplingMixture defensive_mixture(const render::SamplingMixture& a, const render::SamplingMixture& b);

/// `settings` with the mixture fitted to the model for its sampler: what render_basis uses, and
/// what a direct render of a map point must use to equal the composition of the basis.
render::RenderSettings model_render_settings(const Model& model, render::RenderSettings settings);

}  // namespace matlas::atlas
