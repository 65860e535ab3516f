#include "artist/pbr_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "brdf/albedo.h"
#include "brdf/analytic_microfacet.h"
#include "brdf/merl_grid.h"
#include "core/error.h"
#include "core/parallel.h"
#include "gp/minimize.h"

namespace matlas::artist {

namespace {

struct Sample {
  PbrCosines cosines;
  double weight = 0;                // c = cos_i cos_o
  double measure = 0;               // the bin's share of the (wi, wo) measure
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
        // dwi dwo = 4 cos(theta_d) dw_h dw_d; theta_h = (pi/2) u^2 makes d theta_h / di grow as
        // u, i.e. as i + 0.5 (constant factors dropped: the weights are normalised).
        const HalfDiffAngles a = bin_centre(dims, i, j, k);
        s.measure = std::cos(a.theta_d) * std::sin(a.theta_d) * std::sin(a.theta_h) * (i + 0.5);
        for (int c = 0; c < 3; ++c) s.target[static_cast<std::size_t>(c)] = std::cbrt(s.weight * f[c]);
        samples.push_back(s);
      }
  return samples;
}

const double kLogMinRoughness = 0.5 * std::log(microfacet::kMinAlpha);

// The search's coordinates: base colour, metallic, specular and clearcoat as they are (in [0, 1]),
// the two roughnesses by log(r) / 4 (in [-0.86, 0]: a step of 0.1 is a factor 1.5 in r), so that
// one step size suits them all. Outside the box the model is evaluated at the nearest point in it
// and the objective pays the squared distance to it (kOutside per unit^2), which sends the
// simplex back without the flat regions of a logistic map near the bounds.
constexpr double kOutside = 1.0;

double roughness_of(double u) { return std::exp(4.0 * std::clamp(u, kLogMinRoughness / 4.0, 0.0)); }
double log_roughness(double r) { return std::log(std::max(r, std::exp(kLogMinRoughness))) / 4.0; }

const double kLogMinSheenRoughness = std::log(GltfPbr::kMinSheenRoughness);

/// A start of the search in terms both models share: the glTF specular factor s (F0 = 0.04 s of a
/// dielectric), the others as named.
struct Start {
  Rgb base = Rgb::Zero();
  double metallic = 0, roughness = 0.5, specular = 1, clearcoat = 0, clearcoat_roughness = 0.5;
};

/// The glTF model's coordinates: x[0..2] base colour, x[3] metallic, x[4] log(r) / 4, x[5] the
/// specular factor, x[6] clearcoat, x[7] log(clearcoat r) / 4; the sheen stage adds x[8] a neutral
/// sheen colour and x[9] log(sheen roughness) / 4.
struct GltfSpace {
  using Fitted = GltfPbr;
  double ior = 1.5;

  Fitted at(const Eigen::VectorXd& x) const {
    GltfPbr m;
    for (int c = 0; c < 3; ++c) m.base_color[c] = std::clamp(x[c], 0.0, 1.0);
    m.metallic = std::clamp(x[3], 0.0, 1.0);
    m.roughness = roughness_of(x[4]);
    m.specular = std::clamp(x[5], 0.0, 1.0);
    m.clearcoat = std::clamp(x[6], 0.0, 1.0);
    m.clearcoat_roughness = roughness_of(x[7]);
    m.ior = ior;
    if (x.size() > 8) {
      m.sheen_color = Rgb::Constant(std::clamp(x[8], 0.0, 1.0));
      m.sheen_roughness = std::exp(4.0 * std::clamp(x[9], kLogMinSheenRoughness / 4.0, 0.0));
    }
    return m;
  }
  static std::pair<double, double> bounds(Eigen::Index k) {
    if (k == 4 || k == 7) return {kLogMinRoughness / 4.0, 0.0};
    if (k == 9) return {kLogMinSheenRoughness / 4.0, 0.0};
    return {0.0, 1.0};
  }
  static Eigen::VectorXd coordinates(const Start& s) {
    Eigen::VectorXd x(8);
    x << std::clamp(s.base[0], 0.0, 1.0), std::clamp(s.base[1], 0.0, 1.0), std::clamp(s.base[2], 0.0, 1.0), s.metallic,
        log_roughness(s.roughness), s.specular, s.clearcoat, log_roughness(s.clearcoat_roughness);
    return x;
  }
  /// A neutral sheen of two strengths and two roughnesses.
  static std::vector<Eigen::VectorXd> sheen_starts(const Eigen::VectorXd& best) {
    std::vector<Eigen::VectorXd> starts;
    for (const double strength : {0.3, 0.8})
      for (const double roughness : {0.3, 0.7}) {
        Eigen::VectorXd start(10);
        start << best, strength, std::log(roughness) / 4.0;
        starts.push_back(start);
      }
    return starts;
  }
  static void tidy(Fitted& m) {
    if (m.sheen_color.maxCoeff() == 0.0) m.sheen_roughness = 0.0;  // no sheen: no roughness
  }
};

/// Blender's Principled v1: the same eight coordinates, x[5] its "Specular" (F0 = 0.08 x[5]), x[6]
/// and x[7] the coat layer's weight and log(roughness) / 4; the sheen stage adds x[8] "Sheen" and
/// x[9] "Sheen Tint". "Specular Tint" stays 0 (Blender's default).
struct PrincipledV1Space {
  using Fitted = PrincipledV1;

  Fitted at(const Eigen::VectorXd& x) const {
    PrincipledV1 m;
    for (int c = 0; c < 3; ++c) m.base_color[c] = std::clamp(x[c], 0.0, 1.0);
    m.metallic = std::clamp(x[3], 0.0, 1.0);
    m.roughness = roughness_of(x[4]);
    m.specular = std::clamp(x[5], 0.0, 1.0);
    m.coat = std::clamp(x[6], 0.0, 1.0);
    m.coat_roughness = roughness_of(x[7]);
    if (x.size() > 8) {
      m.sheen = std::clamp(x[8], 0.0, 1.0);
      m.sheen_tint = std::clamp(x[9], 0.0, 1.0);
    }
    return m;
  }
  static std::pair<double, double> bounds(Eigen::Index k) {
    if (k == 4 || k == 7) return {kLogMinRoughness / 4.0, 0.0};
    return {0.0, 1.0};
  }
  /// glTF's F0 = 0.04 s is Principled v1's 0.08 specular; a metal keeps Blender's default 0.5.
  static Eigen::VectorXd coordinates(const Start& s) {
    Start v = s;
    v.specular = s.metallic > 0.5 ? 0.5 : 0.5 * s.specular;
    return GltfSpace::coordinates(v);
  }
  /// Two sheen strengths, untinted and half tinted.
  static std::vector<Eigen::VectorXd> sheen_starts(const Eigen::VectorXd& best) {
    std::vector<Eigen::VectorXd> starts;
    for (const double strength : {0.3, 0.8})
      for (const double tint : {0.0, 0.5}) {
        Eigen::VectorXd start(10);
        start << best, strength, tint;
        starts.push_back(start);
      }
    return starts;
  }
  static void tidy(Fitted& m) {
    if (m.sheen == 0.0) m.sheen_tint = PrincipledV1{}.sheen_tint;  // no sheen: the default tint
  }
};

template <class Space>
double outside_squared(const Eigen::VectorXd& x) {
  double sum = 0;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const auto [lo, hi] = Space::bounds(k);
    const double d = x[k] - std::clamp(x[k], lo, hi);
    sum += d * d;
  }
  return sum;
}

/// What the starts are matched to: the table's back-scattering peak (theta_h bin 0, the first
/// theta_d bins under 5 deg, every phi_d) per channel, the luminance-like mean profile's floor at
/// theta_h = 45 deg, and the theta_h at which the profile falls halfway from its peak to the floor.
struct Peak {
  Rgb value = Rgb::Zero();
  double mean = 0, floor = 0, half_theta = 0;
};

Peak table_peak(const BrdfTable& table) {
  const MerlDims& dims = table.dims();
  const int n_d = std::max(1, static_cast<int>(std::lround(5.0 / 90.0 * dims.theta_d)));
  std::vector<double> profile(static_cast<std::size_t>(dims.theta_h), 0.0);
  Peak p;
  for (int i = 0; i < dims.theta_h; ++i) {
    Rgb sum = Rgb::Zero();
    int count = 0;
    for (int j = 0; j < n_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        bool all = true;
        const Rgb f = table.bin_rgb(dims.flat(i, j, k), &all);
        if (all) sum += f, ++count;
      }
    if (count > 0) sum /= count;
    if (i == 0) p.value = sum;
    profile[static_cast<std::size_t>(i)] = sum.mean();
  }
  p.mean = profile[0];
  const int i45 = std::clamp(theta_h_index(kPi / 4, dims.theta_h), 0, dims.theta_h - 1);
  p.floor = std::min(p.mean, profile[static_cast<std::size_t>(i45)]);
  p.half_theta = theta_h_centre(dims.theta_h - 1, dims.theta_h);
  for (int i = 0; i < dims.theta_h; ++i)
    if (profile[static_cast<std::size_t>(i)] - p.floor <= 0.5 * (p.mean - p.floor)) {
      p.half_theta = theta_h_centre(i, dims.theta_h);
      break;
    }
  return p;
}

/// Mean squared cube-root difference over the samples weighted by their measure, summed in fixed
/// chunks (deterministic).
template <class Fitted>
double objective(const std::vector<Sample>& samples, const Fitted& m) {
  constexpr std::size_t kChunk = 2048;
  const std::size_t chunks = (samples.size() + kChunk - 1) / kChunk;
  std::vector<double> sums(chunks, 0.0), measures(chunks, 0.0);
  parallel_for_each(0, chunks, [&](std::size_t k) {
    double sum = 0, measure = 0;
    const std::size_t end = std::min(samples.size(), (k + 1) * kChunk);
    for (std::size_t s = k * kChunk; s < end; ++s) {
      const Sample& p = samples[s];
      const Rgb f = m.evaluate(p.cosines);
      double e = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = std::cbrt(p.weight * f[c]) - p.target[static_cast<std::size_t>(c)];
        e += d * d;
      }
      sum += p.measure * e;
      measure += p.measure;
    }
    sums[k] = sum;
    measures[k] = measure;
  });
  double total = 0, measure = 0;
  for (std::size_t k = 0; k < chunks; ++k) total += sums[k], measure += measures[k];
  return total / (3.0 * measure);
}

template <class Space>
AnalyticFit<typename Space::Fitted> fit_in(const Space& space, const BrdfTable& table, const PbrFitOptions& o) {
  if (o.theta_d_stride < 1 || o.phi_d_stride < 1 || o.evaluations_per_start < 1 || o.polish_evaluations < 1)
    throw Error("fit: strides and evaluation budgets must be positive");
  const std::vector<Sample> samples = objective_samples(table, o);
  PbrFitOptions coarse_options = o;
  coarse_options.theta_d_stride *= 2;
  coarse_options.phi_d_stride *= 2;
  const std::vector<Sample> coarse = objective_samples(table, coarse_options);
  if (samples.empty() || coarse.empty()) throw Error("fit: the table has no measured value above the horizon");

  AnalyticFit<typename Space::Fitted> result;
  result.samples = samples.size();
  const auto f = [&](const Eigen::VectorXd& x) {
    ++result.evaluations;
    return objective(samples, space.at(x)) + kOutside * outside_squared<Space>(x);
  };
  const auto f_coarse = [&](const Eigen::VectorXd& x) {
    ++result.evaluations;
    return objective(coarse, space.at(x)) + kOutside * outside_squared<Space>(x);
  };
  // The base colour starts at the table's albedo 30 deg from the normal: the diffuse albedo of a
  // dielectric, about F0 of a conductor.
  const Rgb albedo = directional_albedo(table, 30.0 * kPi / 180.0);
  Eigen::VectorXd best;
  double best_value = 0;
  // Starts matched to the table's peak: a GGX lobe D(h) falls to half its peak at
  // tan(theta_h) = 0.644 alpha, and its peak is 1 / (4 pi alpha^2) times the Fresnel weight, which
  // gives a roughness, the specular factor of a dielectric (F0 = 0.04) and the F0 (base colour) of
  // a metal. Dielectric and metal at that roughness, twice it and 0.5, and both rough (0.5) under a
  // coat of that roughness (metallic paints, varnished materials).
  const Peak peak = table_peak(table);
  const double r_peak = std::sqrt(std::clamp(std::tan(peak.half_theta) / 0.644, microfacet::kMinAlpha, 1.0));
  const auto lobe_peak = [](double r) { return 1.0 / (4.0 * kPi * std::pow(r, 4)); };
  const auto fresnel_weight = [&](double r) {  // the dielectric F0 times the specular factor
    return std::clamp((peak.mean - albedo.mean() / kPi) / lobe_peak(r), 0.0, 1.0);
  };
  std::vector<Eigen::VectorXd> starts;
  for (const double r : {r_peak, std::min(1.0, 2.0 * r_peak), 0.5}) {
    const double s = std::clamp(fresnel_weight(r) / 0.04, 0.002, 1.0);
    starts.push_back(Space::coordinates({albedo, 0.0, r, s, 0.0, r_peak}));
    const Rgb f0 = (peak.value / lobe_peak(r)).cwiseMax(0.02).cwiseMin(1.0);
    starts.push_back(Space::coordinates({f0, 1.0, r, 1.0, 0.0, r_peak}));
  }
  const double coat = std::clamp(fresnel_weight(r_peak) / 0.04, 0.002, 1.0);
  starts.push_back(Space::coordinates({albedo, 0.0, 0.5, 1.0, coat, r_peak}));
  starts.push_back(Space::coordinates({albedo, 1.0, 0.5, 1.0, coat, r_peak}));
  // Nelder-Mead from each start on the coarse subsample, the best polished on the full one.
  const auto search = [&](const std::vector<Eigen::VectorXd>& from, double step) {
    Eigen::VectorXd x_best;
    double v_best = 0;
    for (const Eigen::VectorXd& start : from) {
      const Eigen::VectorXd x =
          gp::minimize_nelder_mead(f_coarse, start, gp::MinimizeOptions::nelder_mead(step, o.evaluations_per_start));
      const double v = f_coarse(x);
      ++result.starts;
      if (x_best.size() == 0 || v < v_best) {
        x_best = x;
        v_best = v;
      }
    }
    x_best = gp::minimize_nelder_mead(f, x_best, gp::MinimizeOptions::nelder_mead(0.05, o.polish_evaluations));
    return std::pair<Eigen::VectorXd, double>(x_best, f(x_best));
  };
  // A restart from the result (the convergence check): kept if lower, and its gain recorded.
  const auto restart = [&](Eigen::VectorXd& x, double& value) {
    const Eigen::VectorXd again = gp::minimize_nelder_mead(f, x, gp::MinimizeOptions::nelder_mead(0.02, o.restart_evaluations));
    const double v = f(again);
    result.restart_gain = 0.0;
    if (v < value) {
      result.restart_gain = std::sqrt(value) - std::sqrt(v);
      x = again;
      value = v;
    }
  };
  std::tie(best, best_value) = search(starts, 0.2);
  restart(best, best_value);
  // The sheen stage (fabrics' grazing brightening: KHR_materials_sheen, or Principled v1's
  // Sheen): from the result with sheens of two strengths, all parameters free; kept only if it
  // lowers the distance by more than `sheen_gain`, so materials without a sheen keep the
  // eight-parameter fit as it was.
  if (o.sheen) {
    const std::vector<Eigen::VectorXd> sheen_starts = Space::sheen_starts(best);
    auto [sheen_best, sheen_value] = search(sheen_starts, 0.1);
    if (std::sqrt(sheen_value) < (1.0 - o.sheen_gain) * std::sqrt(best_value)) {
      restart(sheen_best, sheen_value);
      best = sheen_best;
      best_value = sheen_value;
    }
  }
  result.model = space.at(best);
  Space::tidy(result.model);
  result.distance = std::sqrt(best_value);
  return result;
}

}  // namespace

PbrFitResult fit_gltf_pbr(const BrdfTable& table, const PbrFitOptions& o) { return fit_in(GltfSpace{o.ior}, table, o); }

PrincipledV1FitResult fit_principled_v1(const BrdfTable& table, const PbrFitOptions& o) {
  return fit_in(PrincipledV1Space{}, table, o);
}

}  // namespace matlas::artist
