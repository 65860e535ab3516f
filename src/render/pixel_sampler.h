#pragma once
// Stratified, material-independent random numbers for the previews' estimator (render/render.h,
// RenderSettings::sampler = Sampler::stratified).
//
// The spp samples of a pixel are split among the mixture's strategies in fixed counts
// (plan_strategies: n_k = the mixture's probability times spp, largest remainders), and the
// estimator weighs every sample with the density of those counts, sum_k (n_k / spp) pdf_k: the
// multi-sample balance heuristic (Veach 1997, 9.2.2), unbiased for fixed counts. Within a
// strategy, sample j takes point j of the 4D Sobol sequence (jitter x, jitter y, then the
// direction's two numbers), shuffled and Owen-scrambled per dimension by hashes (Burley 2020,
// "Practical hash-based Owen scrambling") seeded by (seed, pixel, strategy). The jitter and the
// direction are stratified JOINTLY: the few samples whose direction lands in a sharp lobe (a
// chrome's tabulated bins, a small bright light) still spread over the pixel's footprint, which
// is what a mirror's reflection of a bright edge needs.
//
// Nothing depends on the material: every table of a basis sees the same directions and weights,
// so the images stay linear in the BRDF.
#include <cstdint>
#include <vector>

#include "render/sampling_mixture.h"

namespace matlas::render {

/// The 32-bit Owen scrambling of v (bits from the most significant one) keyed by seed.
std::uint32_t owen_scramble(std::uint32_t v, std::uint32_t seed);

/// Point `index` of the first four dimensions of the Sobol sequence (van der Corput, then Joe &
/// Kuo's direction numbers) as 32-bit fractions, without scrambling. Dimensions 0 and 1 form a
/// (0,2)-sequence. Table-driven (a byte of the index per lookup).
void sobol_4d(std::uint32_t index, std::uint32_t out[4]);
/// Coordinate `dimension` (0..3) of the same point, from the generator matrix a bit at a time:
/// the definition (sobol_4d's tables are built from it; tests compare the two).
std::uint32_t sobol_dimension(int dimension, std::uint32_t index);

/// The strategies of a mixture in a fixed order: environment, cosine, the GGX lobes, the
/// tabulated lobe, with the number of samples each takes per pixel.
struct StrategyPlan {
  std::vector<int> counts;   ///< samples per strategy; sum = spp
  std::vector<double> pick;  ///< for k >= 1: u that makes density.sample_local draw from strategy k
  /// The mixture with probabilities counts / spp: the density of the pixel's samples.
  SamplingMixture density;
};

/// Splits spp samples among the strategies of `mixture` (largest remainders; ties to the
/// earlier strategy). Strategies of probability 0 get none.
StrategyPlan plan_strategies(const SamplingMixture& mixture, int spp);

/// The stratified numbers of one pixel.
class PixelSampler {
public:
  PixelSampler(std::uint64_t seed, std::uint64_t pixel) : key_(mix(seed ^ mix(pixel + 0x632BE59BD9B4E019ull))) {}
  /// Sample j of strategy k: u[0], u[1] the camera jitter, u[2], u[3] the direction; in [0, 1).
  void point(int strategy, int j, double u[4]) const;

private:
  static std::uint64_t mix(std::uint64_t z);
  std::uint64_t key_;
};

}  // namespace matlas::render
