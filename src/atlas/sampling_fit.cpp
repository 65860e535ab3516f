#include "atlas/sampling_fit.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "atlas/model_bank.h"
#include "brdf/merl_grid.h"
#include "core/check.h"

namespace matlas::atlas {

namespace {

constexpr double kDegree = kPi / 180.0;

/// theta_h at boundary i of the MERL grid's n bins.
double theta_h_edge(std::size_t i, int n) {
  const double t = static_cast<double>(i) / static_cast<double>(n);
  return t * t * 0.5 * kPi;
}

double luminance(const double* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

/// Per material of [first, count) of the bank (ModelBank's first is its mean): the lobe's width
/// (0: no lobe); and the pool of every glossy material's three width estimates.
struct LobeFit {
  std::vector<double> widths, pool;
  std::vector<double> bins;  ///< sum over glossy materials of their normalised lobe energy per theta_h bin
};

LobeFit lobe_widths(const render::MaterialBank& bank, int first) {
  const int n = bank.count();
  const MerlDims dims;
  std::vector<std::vector<double>> profile(static_cast<std::size_t>(n));
  std::vector<double> theta;
  std::vector<double> values(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < dims.theta_h; ++i) {
    const double th = theta_h_centre(i, dims.theta_h);
    if (th > 70.0 * kDegree) break;
    HalfDiffAngles a;
    a.theta_h = th;
    a.theta_d = 10.0 * kDegree;
    a.phi_d = 90.0 * kDegree;
    const DirectionPair d = from_half_diff(a);
    if (d.wi.z() <= 0 || d.wo.z() <= 0) break;
    bank.eval_all(d.wi, d.wo, values.data());
    theta.push_back(th);
    for (int k = 0; k < n; ++k) profile[static_cast<std::size_t>(k)].push_back(luminance(&values[3 * static_cast<std::size_t>(k)]));
  }
  // Per material, the lobe's energy over theta_h: (f - floor) sin(2 theta_h) d theta_h at the bin
  // centres (the projected solid angle of the half vector, up to constants). A GGX lobe of width
  // alpha sampled by D(h) cos(theta_h) puts the fraction u = tan^2 / (alpha^2 + tan^2) below
  // theta_h: its quartiles and median give three estimates of alpha.
  LobeFit fit;
  for (int k = first; k < n; ++k) {
    const std::vector<double>& p = profile[static_cast<std::size_t>(k)];
    std::vector<double> alphas;
    if (p.size() >= 2) {
      const double floor = std::max(0.0, *std::min_element(p.begin(), p.end()));
      if (p.front() > 2.0 * floor && p.front() > 0) {
        std::vector<double> cdf(p.size() + 1, 0.0);
        for (std::size_t i = 0; i < p.size(); ++i) {
          const double lo = i == 0 ? 0.0 : 0.5 * (theta[i - 1] + theta[i]);
          const double hi = i + 1 < p.size() ? 0.5 * (theta[i] + theta[i + 1]) : theta[i];
          cdf[i + 1] = cdf[i] + std::max(0.0, p[i] - floor) * std::sin(2.0 * theta[i]) * (hi - lo);
        }
        std::vector<double> energy(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
          const double a = theta_h_edge(i, dims.theta_h), b = theta_h_edge(i + 1, dims.theta_h);
          energy[i] = std::max(0.0, p[i] - floor) * std::cos(theta[i]) * (std::cos(a) - std::cos(b));
        }
        const double e_total = std::accumulate(energy.begin(), energy.end(), 0.0);
        fit.bins.resize(static_cast<std::size_t>(dims.theta_h), 0.0);
        if (e_total > 0)
          for (std::size_t i = 0; i < p.size(); ++i) fit.bins[i] = std::max(fit.bins[i], energy[i] / e_total);
        for (const auto& [u, scale] : {std::pair{0.25, std::sqrt(3.0)}, std::pair{0.5, 1.0}, std::pair{0.75, 1.0 / std::sqrt(3.0)}}) {
          const double target = u * cdf.back();
          std::size_t i = 0;
          while (i + 1 < p.size() && cdf[i + 1] < target) ++i;
          const double lo = i == 0 ? 0.0 : 0.5 * (theta[i - 1] + theta[i]);
          const double hi = i + 1 < p.size() ? 0.5 * (theta[i] + theta[i + 1]) : theta[i];
          const double t = (target - cdf[i]) / std::max(cdf[i + 1] - cdf[i], 1e-300);
          alphas.push_back(std::tan(lo + std::clamp(t, 0.0, 1.0) * (hi - lo)) * scale);
        }
      }
    }
    fit.widths.push_back(alphas.empty() ? 0.0 : alphas[1]);
    fit.pool.insert(fit.pool.end(), alphas.begin(), alphas.end());
  }
  return fit;
}

render::SamplingMixture mixture_from_fit(const LobeFit& fit, const SamplingFitOptions& o) {
  std::vector<double> widths = fit.pool;
  std::erase_if(widths, [](double a) { return !(a > 0); });
  if (widths.empty()) return render::SamplingMixture::preview_default();
  for (double& a : widths) a = std::log(std::clamp(a, o.min_alpha, o.max_alpha));
  std::sort(widths.begin(), widths.end());
  render::SamplingMixture m;
  m.environment = o.environment;
  m.cosine = o.cosine;
  m.lobes.clear();
  double sharpest = 0;
  for (double a : fit.widths)
    if (a > 0 && (sharpest == 0 || a < sharpest)) sharpest = a;
  if (o.sharpest_share > 0 && sharpest > 0) m.lobes.emplace_back(std::clamp(sharpest, o.min_alpha, o.max_alpha), o.sharpest_share);
  const double each = o.lobe_share / static_cast<double>(o.quantiles.size());
  for (double q : o.quantiles) {
    const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(widths.size() - 1);
    const auto lo = static_cast<std::size_t>(pos);
    const std::size_t hi = std::min(lo + 1, widths.size() - 1);
    const double alpha = std::exp(widths[lo] + (pos - static_cast<double>(lo)) * (widths[hi] - widths[lo]));
    if (!m.lobes.empty() && alpha < 1.5 * m.lobes.back().first)
      m.lobes.back().second += each;  // merge near-equal widths
    else
      m.lobes.emplace_back(alpha, each);
  }
  m.set_profile(fit.bins, o.tabulated);
  return m;
}

}  // namespace

std::vector<double> specular_lobe_widths(const render::MaterialBank& bank) { return lobe_widths(bank, 0).widths; }

render::SamplingMixture fit_sampling_mixture(const render::MaterialBank& bank, const SamplingFitOptions& options) {
  return mixture_from_fit(lobe_widths(bank, 0), options);
}

render::SamplingMixture fit_sampling_mixture(const Model& model, const SamplingFitOptions& options) {
  return mixture_from_fit(lobe_widths(ModelBank(model), 1), options);
}

SamplingFitOptions SamplingFitOptions::for_sampler(render::Sampler sampler) {
  SamplingFitOptions o;
  if (sampler == render::Sampler::light_and_lobe) {
    o.cosine = 0.1;
    o.sharpest_share = 0.45;
    o.tabulated = 0.1;
  }
  return o;
}

render::RenderSettings model_render_settings(const Model& model, render::RenderSettings settings) {
  settings.mixture = fit_sampling_mixture(model, SamplingFitOptions::for_sampler(settings.sampler));
  return settings;
}

render::SamplingMixture defensive_mixture(const render::SamplingMixture& a, const render::SamplingMixture& b) {
  const double ta = a.total(), tb = b.total();
  MATLAS_CHECK(ta > 0 && tb > 0);
  render::SamplingMixture m(0.5 * (a.environment / ta + b.environment / tb), 0.5 * (a.cosine / ta + b.cosine / tb), {});
  for (const auto& [alpha, p] : a.lobes) m.lobes.emplace_back(alpha, 0.5 * p / ta);
  for (const auto& [alpha, p] : b.lobes) m.lobes.emplace_back(alpha, 0.5 * p / tb);
  const double pa = a.profile().empty() ? 0.0 : 0.5 * a.tabulated / ta;
  const double pb = b.profile().empty() ? 0.0 : 0.5 * b.tabulated / tb;
  if (pa + pb > 0) {
    const std::size_t n = std::max(a.profile().size(), b.profile().size());
    MATLAS_CHECK(pa == 0 || pb == 0 || a.profile().size() == b.profile().size());
    std::vector<double> bins(n, 0.0);
    for (std::size_t i = 0; i < a.profile().size(); ++i) bins[i] += pa * a.profile()[i];
    for (std::size_t i = 0; i < b.profile().size(); ++i) bins[i] += pb * b.profile()[i];
    m.set_profile(std::move(bins), pa + pb);
  }
  return m;
}

}  // namespace matlas::atlas
