#include "render/pixel_sampler.h"

#include <algorithm>
#include <array>
#include <numeric>

#include "core/check.h"
#include "core/error.h"

namespace matlas::render {

namespace {

std::uint32_t reverse_bits(std::uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
  return (v >> 16) | (v << 16);
}

/// A bijection of 32-bit words in which output bit k depends only on input bits 0..k (products,
/// sums and xors of left-shifted copies): applied to the bit-reversed word, each bit is flipped as
/// a function of the bits above it, which is Owen's nested scrambling (Burley 2020's constants).
std::uint32_t upward_hash(std::uint32_t x, std::uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

constexpr double kTwoToMinus32 = 1.0 / 4294967296.0;

}  // namespace

std::uint32_t owen_scramble(std::uint32_t v, std::uint32_t seed) {
  return reverse_bits(upward_hash(reverse_bits(v), seed));
}

namespace {

/// Generator matrix (its 32 columns) of a Sobol dimension from its primitive polynomial of degree
/// s with inner coefficients a, and initial direction integers m (Bratley & Fox's recurrence).
std::array<std::uint32_t, 32> sobol_matrix(int s, std::uint32_t a, std::array<std::uint32_t, 3> m_init) {
  std::array<std::uint32_t, 32> m{};
  for (int i = 0; i < s; ++i) m[static_cast<std::size_t>(i)] = m_init[static_cast<std::size_t>(i)];
  for (int i = s; i < 32; ++i) {
    const auto at = [&](int k) { return m[static_cast<std::size_t>(i - k)]; };
    std::uint32_t v = at(s) ^ (at(s) << s);
    for (int k = 1; k < s; ++k)
      if ((a >> (s - 1 - k)) & 1u) v ^= at(k) << k;
    m[static_cast<std::size_t>(i)] = v;
  }
  std::array<std::uint32_t, 32> columns{};
  for (int i = 0; i < 32; ++i) columns[static_cast<std::size_t>(i)] = m[static_cast<std::size_t>(i)] << (31 - i);
  return columns;
}

/// Dimensions 1-3 of the Sobol sequence (dimension 0 is van der Corput): the polynomials x + 1,
/// x^2 + x + 1 and x^3 + x + 1 with Joe & Kuo's initial numbers (1), (1, 3), (1, 3, 1).
const std::array<std::array<std::uint32_t, 32>, 3>& sobol_matrices() {
  static const std::array<std::array<std::uint32_t, 32>, 3> matrices = {
      sobol_matrix(1, 0, {1, 0, 0}), sobol_matrix(2, 1, {1, 3, 0}), sobol_matrix(3, 1, {1, 3, 1})};
  return matrices;
}

}  // namespace

std::uint32_t sobol_dimension(int dimension, std::uint32_t index) {
  if (dimension == 0) return reverse_bits(index);
  const auto& m = sobol_matrices()[static_cast<std::size_t>(dimension - 1)];
  std::uint32_t r = 0;
  for (std::uint32_t i = index, b = 0; i; i >>= 1, ++b)
    if (i & 1u) r ^= m[b];
  return r;
}

namespace {

/// The matrix-vector product over GF(2) a byte at a time: for dimension d and byte position k,
/// entry v is the product with v's bits placed at byte k (the xor of columns 8k + b for the set
/// bits b of v). The pixels' indices are scrambled (any 32-bit word), so a bit-by-bit product
/// costs up to 32 steps per dimension; this is four lookups (12 KB, in L1).
struct SobolByteTables {
  std::array<std::array<std::array<std::uint32_t, 256>, 4>, 3> t{};
  SobolByteTables() {
    for (std::size_t d = 0; d < 3; ++d)
      for (std::size_t k = 0; k < 4; ++k)
        for (std::uint32_t v = 0; v < 256; ++v) t[d][k][v] = sobol_dimension(static_cast<int>(d) + 1, v << (8 * k));
  }
};

}  // namespace

void sobol_4d(std::uint32_t index, std::uint32_t out[4]) {
  static const SobolByteTables tables;
  out[0] = reverse_bits(index);
  for (std::size_t d = 0; d < 3; ++d) {
    const auto& t = tables.t[d];
    out[d + 1] = t[0][index & 0xFFu] ^ t[1][(index >> 8) & 0xFFu] ^ t[2][(index >> 16) & 0xFFu] ^ t[3][index >> 24];
  }
}

StrategyPlan plan_strategies(const SamplingMixture& mixture, int spp) {
  if (spp <= 0) throw Error("samples per pixel must be positive, got " + std::to_string(spp));
  std::vector<double> p = {mixture.environment, mixture.cosine};
  for (const auto& lobe : mixture.lobes) p.push_back(lobe.second);
  p.push_back(mixture.profile().empty() ? 0.0 : mixture.tabulated);
  const double total = std::accumulate(p.begin(), p.end(), 0.0);
  if (!(total > 0)) throw Error("sampling mixture: all probabilities are zero");
  StrategyPlan plan;
  plan.counts.assign(p.size(), 0);
  std::vector<double> remainder(p.size());
  int used = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double share = p[k] / total * spp;
    plan.counts[k] = static_cast<int>(share);
    remainder[k] = p[k] > 0 ? share - plan.counts[k] : -1.0;
    used += plan.counts[k];
  }
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
  for (std::size_t i = 0; used < spp; i = (i + 1) % order.size())
    if (remainder[order[i]] >= 0) ++plan.counts[order[i]], ++used;
  MATLAS_CHECK_EQ(std::accumulate(plan.counts.begin(), plan.counts.end(), 0), spp);
  // The density: the same mixture with the allocated counts as its probabilities.
  plan.density = mixture;
  plan.density.environment = plan.counts[0];
  plan.density.cosine = plan.counts[1];
  for (std::size_t l = 0; l < mixture.lobes.size(); ++l) plan.density.lobes[l].second = plan.counts[2 + l];
  plan.density.tabulated = plan.counts.back();
  // SamplingMixture::sample_local picks by u * total in the order above: the middle of each
  // strategy's interval selects it.
  plan.pick.assign(p.size(), 0.0);
  double start = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    plan.pick[k] = (start + 0.5 * plan.counts[k]) / spp;
    start += plan.counts[k];
  }
  return plan;
}

std::uint64_t PixelSampler::mix(std::uint64_t z) {  // splitmix64 finaliser
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void PixelSampler::point(int strategy, int j, double u[4]) const {
  std::uint64_t h = mix(key_ + 0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(strategy) + 1));
  std::uint32_t x[4];
  sobol_4d(owen_scramble(static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(h)), x);
  for (int d = 0; d < 4; ++d) {
    h = mix(h + 0xD1B54A32D192ED03ull);
    u[d] = owen_scramble(x[d], static_cast<std::uint32_t>(h)) * kTwoToMinus32;
  }
}

}  // namespace matlas::render
