#include "artist/pbr_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "brdf/albedo.h"
#include "brdf/analytic_microfacet.h"
#include "brdf/merl_grid.h"
#include "core/error.h"
#include "core/parallel.h"
#include "gp/nelder_mead.h"

namespace matlas::artist {

namespace {

struct Sample {
  PbrCosines cosines;
  double weight = 0;                // c = cos_i cos_o
  std::array<double, 3> target{};  // cbrt(c f_table) per channel
};

std::vector<Sample> objective_samples(const BrdfTable& table, const PbrFitOptions& o) {
  const MerlDims& dims = table.dims();
  std::vector<Sample> samples;
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = o.theta_d_stride / 2; j < dims.theta_d; j += o.theta_d_stride)
      for (int k = o.phi_d_stride / 2; k < dims.phi_d; k += o.phi_d_stride) {
        const DirectionPair p = from_half_diff(bin_centre(dims, i, j, k));
        if (p.wi.z() <= 1e-6 || p.wo.z() <= 1e-6) continue;
        const std::size_t bin = dims.flat(i, j, k);
        bool all_measured = true;
        const Rgb f = table.bin_rgb(bin, &all_measured);
        if (!all_measured) continue;
        Sample s;
        s.cosines = pbr_cosines(p.wi, p.wo);
        s.weight = p.wi.z() * p.wo.z();
        for (int c = 0; c < 3; ++c) s.target[static_cast<std::size_t>(c)] = std::cbrt(s.weight * f[c]);
        samples.push_back(s);
      }
  return samples;
}

double logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }
double logit(double p) { return std::log(p / (1.0 - p)); }

const double kMinRoughness = std::sqrt(microfacet::kMinAlpha);

GltfPbr model_at(const Eigen::VectorXd& x, double ior) {
  GltfPbr m;
  for (int c = 0; c < 3; ++c) m.base_color[c] = logistic(x[c]);
  m.metallic = logistic(x[3]);
  m.roughness = kMinRoughness + (1.0 - kMinRoughness) * logistic(x[4]);
  m.specular = logistic(x[5]);
  m.ior = ior;
  return m;
}

Eigen::VectorXd coordinates_of(const Rgb& base, double metallic, double roughness, double specular) {
  Eigen::VectorXd x(6);
  for (int c = 0; c < 3; ++c) x[c] = logit(std::clamp(base[c], 0.02, 0.98));
  x[3] = logit(metallic);
  x[4] = logit((roughness - kMinRoughness) / (1.0 - kMinRoughness));
  x[5] = logit(specular);
  return x;
}

/// Mean squared cube-root difference over the samples, summed in fixed chunks (deterministic).
double objective(const std::vector<Sample>& samples, const GltfPbr& m) {
  constexpr std::size_t kChunk = 2048;
  const std::size_t chunks = (samples.size() + kChunk - 1) / kChunk;
  std::vector<double> sums(chunks, 0.0);
  parallel_for_each(0, chunks, [&](std::size_t k) {
    double sum = 0;
    const std::size_t end = std::min(samples.size(), (k + 1) * kChunk);
    for (std::size_t s = k * kChunk; s < end; ++s) {
      const Sample& p = samples[s];
      const Rgb f = m.evaluate(p.cosines);
      for (int c = 0; c < 3; ++c) {
        const double d = std::cbrt(p.weight * f[c]) - p.target[static_cast<std::size_t>(c)];
        sum += d * d;
      }
    }
    sums[k] = sum;
  });
  double total = 0;
  for (double s : sums) total += s;
  return total / (3.0 * static_cast<double>(samples.size()));
}

}  // namespace

PbrFitResult fit_gltf_pbr(const BrdfTable& table, const PbrFitOptions& o) {
  if (o.theta_d_stride < 1 || o.phi_d_stride < 1 || o.evaluations_per_start < 1 || o.polish_evaluations < 1)
    throw Error("fit: strides and evaluation budgets must be positive");
  const std::vector<Sample> samples = objective_samples(table, o);
  PbrFitOptions coarse_options = o;
  coarse_options.theta_d_stride *= 2;
  coarse_options.phi_d_stride *= 2;
  const std::vector<Sample> coarse = objective_samples(table, coarse_options);
  if (samples.empty() || coarse.empty()) throw Error("fit: the table has no measured value above the horizon");

  PbrFitResult result;
  result.samples = samples.size();
  const auto f = [&](const Eigen::VectorXd& x) {
    ++result.evaluations;
    return objective(samples, model_at(x, o.ior));
  };
  const auto f_coarse = [&](const Eigen::VectorXd& x) {
    ++result.evaluations;
    return objective(coarse, model_at(x, o.ior));
  };
  // The base colour starts at the table's albedo 30 deg from the normal: the diffuse albedo of a
  // dielectric, about F0 of a conductor.
  const Rgb albedo = directional_albedo(table, 30.0 * kPi / 180.0);
  Eigen::VectorXd best;
  double best_value = 0;
  for (const double metallic : {0.05, 0.95})
    for (const double roughness : {0.15, 0.35, 0.65}) {
      const Eigen::VectorXd x = gp::nelder_mead(f_coarse, coordinates_of(albedo, metallic, roughness, 0.7), 1.0,
                                                o.evaluations_per_start);
      const double v = f_coarse(x);
      ++result.starts;
      if (best.size() == 0 || v < best_value) {
        best = x;
        best_value = v;
      }
    }
  best = gp::nelder_mead(f, best, 0.25, o.polish_evaluations);
  best_value = f(best);
  const Eigen::VectorXd restarted = gp::nelder_mead(f, best, 0.05, o.restart_evaluations);
  const double restarted_value = f(restarted);
  if (restarted_value < best_value) {
    result.restart_gain = std::sqrt(best_value) - std::sqrt(restarted_value);
    best = restarted;
    best_value = restarted_value;
  }
  result.model = model_at(best, o.ior);
  result.cbrt_distance = std::sqrt(best_value);
  return result;
}

}  // namespace matlas::artist
