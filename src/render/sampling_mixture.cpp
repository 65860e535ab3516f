#include "render/sampling_mixture.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/error.h"
#include "render/sampling.h"

namespace matlas::render {

namespace {

/// theta_h edge of MERL bin boundary i of n.
double theta_h_edge(std::size_t i, std::size_t n) {
  const double t = static_cast<double>(i) / static_cast<double>(n);
  return t * t * 0.5 * kPi;
}

}  // namespace

void SamplingMixture::set_profile(std::vector<double> bin_weights, double probability) {
  double sum = 0;
  for (double& w : bin_weights) sum += (w = std::max(0.0, std::isfinite(w) ? w : 0.0));
  if (!(sum > 0) || !(probability > 0)) {
    profile_.clear(), cdf_.clear(), density_.clear();
    tabulated = 0;
    return;
  }
  const std::size_t n = bin_weights.size();
  profile_ = std::move(bin_weights);
  cdf_.assign(n + 1, 0.0);
  density_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    profile_[i] /= sum;
    cdf_[i + 1] = cdf_[i] + profile_[i];
    const double solid = 2.0 * kPi * (std::cos(theta_h_edge(i, n)) - std::cos(theta_h_edge(i + 1, n)));
    density_[i] = profile_[i] / solid;
  }
  cdf_[n] = 1.0;
  tabulated = probability;
}

double SamplingMixture::total() const {
  double t = environment + cosine + tabulated;
  for (const auto& l : lobes) t += l.second;
  return t;
}

Vec3 SamplingMixture::sample_local(const Vec3& wo, double u, double u0, double u1) const {
  double pick = u * total() - environment - cosine;
  if (pick < 0) return sample_cosine(u0, u1);
  double lobe_total = 0;
  for (const auto& l : lobes) lobe_total += l.second;
  if ((pick >= lobe_total && tabulated > 0) || lobes.empty()) {
    if (profile_.empty()) return sample_cosine(u0, u1);
    // A bin by u0, then cos(theta_h) uniform over the bin by u0's position inside it.
    const std::size_t n = profile_.size();
    MATLAS_DCHECK_EQ(cdf_.size(), n + 1);
    std::size_t i = static_cast<std::size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u0) - cdf_.begin());
    i = std::min(std::max<std::size_t>(i, 1), n) - 1;
    while (profile_[i] <= 0 && i + 1 < n) ++i;
    const double t = std::clamp((u0 - cdf_[i]) / std::max(profile_[i], 1e-300), 0.0, 1.0);
    const double c0 = std::cos(theta_h_edge(i, n)), c1 = std::cos(theta_h_edge(i + 1, n));
    const double cos_h = c0 + t * (c1 - c0), sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
    const double phi = 2.0 * kPi * u1;
    const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
    return 2.0 * wo.dot(h) * h - wo;
  }
  std::size_t k = 0;
  while (k + 1 < lobes.size() && pick >= lobes[k].second) pick -= lobes[k++].second;
  MATLAS_DCHECK_LT(k, lobes.size());
  return sample_ggx_reflection(wo, lobes[k].first, u0, u1);
}

double SamplingMixture::local_pdf(const Vec3& wo, const Vec3& wi) const {
  double p = cosine * cosine_pdf(wi);
  for (const auto& [alpha, weight] : lobes)
    if (weight > 0) p += weight * ggx_reflection_pdf(wo, wi, alpha);
  if (tabulated > 0 && !profile_.empty() && wi.z() > 0 && wo.z() > 0) {
    const Vec3 h = (wi + wo).normalized();
    const double o_h = wo.dot(h);
    if (o_h > 0 && h.z() > 0) {
      const double theta = std::acos(std::min(1.0, h.z()));
      const std::size_t n = profile_.size();
      const auto i = std::min(n - 1, static_cast<std::size_t>(std::sqrt(theta / (0.5 * kPi)) * static_cast<double>(n)));
      p += tabulated * density_[i] / (4.0 * o_h);
    }
  }
  MATLAS_DCHECK(p >= 0, "a mixture of densities");
  return p / total();
}

double SamplingMixture::sample(const Vec3& wo, double u0, double u1, double u2, Vec3* wi) const {
  *wi = sample_local(wo, u0, u1, u2);
  if (wi->z() <= 0) return 0.0;
  return local_pdf(wo, *wi);
}

void SamplingMixture::validate() const {
  if (environment < 0) throw Error("sampling mixture: negative environment probability");
  if (cosine < 0) throw Error("sampling mixture: negative cosine probability");
  if (tabulated < 0) throw Error("sampling mixture: negative tabulated probability");
  for (const auto& [alpha, weight] : lobes) {
    if (!(alpha > 0 && alpha <= 1)) throw Error("sampling mixture: lobe alpha must be in (0, 1]");
    if (weight < 0) throw Error("sampling mixture: negative lobe probability");
  }
  if (!(total() > 0)) throw Error("sampling mixture: all probabilities are zero");
}

}  // namespace matlas::render
