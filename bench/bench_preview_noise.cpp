// Preview noise (docs/RENDERING.md "Noise"): for named materials of a model, the relative RMS
// difference between two renders that differ only in their seed, with the previews' former fixed
// mixture (render/sampling_mixture.h's defaults) and with the mixture fitted to the model
// (atlas/sampling_fit.h), each with the former independent numbers per sample and with the
// stratified sampler (render/pixel_sampler.h), then the default: the light-and-lobe sampler with
// the mixture fitted for it and the samples of each pixel following its view angle
// (RenderSettings::grazing_samples); then the time of one render with each sampler and of the
// model's preview basis (the defaults).
//
//   bench_preview_noise MODEL ENV SIZE SPP BASIS_SIZE BASIS_SPP MATERIAL...
//
// Relative RMS: sqrt(sum (a - b)^2 / sum ((a + b) / 2)^2) over the pixels fully covered by the
// sphere, all channels; seeds 1 and 2, or pooled over MATLAS_BENCH_PAIRS pairs of seeds (from the
// pair MATLAS_BENCH_FIRST_PAIR, 0 by default). Both renders of a pair use the same mixture, so the number is the
// estimator's noise (sqrt 2 times one image's), independent of any reference.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "atlas/model_basis.h"
#include "atlas/model_bank.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "manifold/model.h"
#include "render/render.h"
#include "render/scene.h"

namespace {

using namespace matlas;

/// Sums of squared differences and of squared means over the pixels fully covered by the sphere.
void accumulate_rms(const Image& a, const Image& b, const std::vector<float>& coverage, double* d, double* s) {
  for (std::size_t p = 0; p < coverage.size(); ++p) {
    if (coverage[p] != 1.0f) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = a.rgb[3 * p + c], y = b.rgb[3 * p + c];
      *d += (x - y) * (x - y);
      *s += 0.25 * (x + y) * (x + y);
    }
  }
}

/// Relative RMS difference between seeds 1 and 2, or pooled over the pairs (1, 2), (3, 4), ...
/// (MATLAS_BENCH_PAIRS; the statistic is dominated by a few pixels that reflect small bright lights,
/// so one pair of seeds is itself a noisy figure).
double seed_noise(const render::Scene& scene, const render::Material& m, render::RenderSettings s,
                  const std::vector<float>& coverage) {
  const char* pairs_env = std::getenv("MATLAS_BENCH_PAIRS");
  const int pairs = pairs_env ? std::max(1, std::atoi(pairs_env)) : 1;
  // MATLAS_BENCH_FIRST_PAIR=k: start at the pair (2k+1, 2k+2): seeds that did not choose the shares.
  const char* first_env = std::getenv("MATLAS_BENCH_FIRST_PAIR");
  const int first = first_env ? std::max(0, std::atoi(first_env)) : 0;
  double d = 0, sum = 0;
  for (int p = first; p < first + pairs; ++p) {
    s.seed = static_cast<std::uint64_t>(2 * p + 1);
    const Image a = render::render(scene, m, s);
    s.seed = static_cast<std::uint64_t>(2 * p + 2);
    const Image b = render::render(scene, m, s);
    accumulate_rms(a, b, coverage, &d, &sum);
  }
  return std::sqrt(d / sum);
}

std::string describe(const render::SamplingMixture& m) {
  std::string out = "env " + std::to_string(m.environment) + ", cosine " + std::to_string(m.cosine) + ", lobes";
  for (const auto& [alpha, weight] : m.lobes) out += " (" + std::to_string(alpha) + ", " + std::to_string(weight) + ")";
  out += ", tabulated " + std::to_string(m.tabulated);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 8) {
    std::fprintf(stderr, "usage: %s MODEL ENV SIZE SPP BASIS_SIZE BASIS_SPP MATERIAL...\n", argv[0]);
    return 2;
  }
  try {
    const Model model = Model::open(argv[1]);
    render::SceneDescription desc;
    desc.environment = argv[2];
    const render::Scene scene(desc);
    render::RenderSettings settings;
    settings.width = settings.height = std::stoi(argv[3]);
    settings.spp = std::stoi(argv[4]);
    // The former sampling: one-sample mixtures with independent numbers per sample, spp in every
    // pixel; the stratified columns also keep spp in every pixel (the default before light and lobe).
    settings.sampler = render::Sampler::independent;
    settings.grazing_samples = 1.0;
    render::RenderSettings fitted = settings, both = settings;
    both.grazing_samples = render::RenderSettings{}.grazing_samples;
    fitted.sampler = render::Sampler::stratified;
    fitted = atlas::model_render_settings(model, fitted);  // the mixture fitted for the stratified sampler
    both.sampler = render::Sampler::light_and_lobe;
    both = atlas::model_render_settings(model, both);  // the default: the mixture fitted for light and lobe
    if (const char* mix = std::getenv("MATLAS_BENCH_MIXTURE")) {  // "env,cosine,alpha:p,alpha:p..." for both
      render::SamplingMixture m = fitted.mixture;
      m.lobes.clear();
      std::sscanf(mix, "%lf,%lf", &m.environment, &m.cosine);
      for (const char* c = std::strchr(std::strchr(mix, ',') + 1, ','); c; c = std::strchr(c + 1, ',')) {
        double a = 0, p = 0;
        std::sscanf(c + 1, "%lf:%lf", &a, &p);
        if (a > 1) m.set_profile(m.profile(), p);  // "2:p": the tabulated lobe's probability
        else m.lobes.emplace_back(a, p);
      }
      fitted.mixture = both.mixture = m;
    }
    std::printf("old mixture:    %s\nfitted mixture (stratified): %s\nfitted mixture (light and lobe): %s\n",
                describe(settings.mixture).c_str(), describe(fitted.mixture).c_str(), describe(both.mixture).c_str());
    render::RenderSettings old_stratified = settings, stratified = fitted;
    // MATLAS_BENCH_STRATIFIED_GRAZING=F: grazing_samples of the "fit strat" column (1 by default).
    if (const char* g = std::getenv("MATLAS_BENCH_STRATIFIED_GRAZING")) stratified.grazing_samples = std::atof(g);
    old_stratified.sampler = render::Sampler::stratified;
    fitted.sampler = render::Sampler::independent;
    // MATLAS_BENCH_GRAZING=F: RenderSettings::grazing_samples of the default (light and lobe)
    // column instead of the default's.
    if (const char* g = std::getenv("MATLAS_BENCH_GRAZING")) both.grazing_samples = std::atof(g);
    // MATLAS_BENCH_POWER=1: the power heuristic in the stratified columns.
    if (std::getenv("MATLAS_BENCH_POWER")) old_stratified.power_heuristic = stratified.power_heuristic = both.power_heuristic = true;
    const std::vector<float> coverage = render::object_coverage(scene, settings);
    const std::vector<double> widths = atlas::specular_lobe_widths(atlas::ModelBank(model));
    std::printf("relative RMS between seeds; independent numbers (former) and stratified (new)\n");
    std::printf("%-28s %10s %10s %10s %10s %10s %8s %10s %8s\n", "material", "lobe alpha", "old", "fitted",
                "old strat", "fit strat", "ratio", "light+lobe", "ratio");
    for (int k = 7; k < argc; ++k) {
      const int i = model.index_of(argv[k]);
      const atlas::ModelMaterial m(model, model.material_weights(i));
      const bool quick = std::getenv("MATLAS_BENCH_NEW_ONLY");  // only the last two columns (ratios meaningless)
      const double old_noise = quick ? 1 : seed_noise(scene, m, settings, coverage);
      const double fitted_noise = quick ? 1 : seed_noise(scene, m, fitted, coverage);
      const double old_strat_noise = quick ? 1 : seed_noise(scene, m, old_stratified, coverage);
      const double new_noise = seed_noise(scene, m, stratified, coverage);
      const double both_noise = seed_noise(scene, m, both, coverage);
      std::printf("%-28s %10.4f %10.4f %10.4f %10.4f %10.4f %8.2f %10.4f %8.2f\n", argv[k],
                  widths[static_cast<std::size_t>(i) + 1], old_noise, fitted_noise, old_strat_noise, new_noise,
                  old_noise / new_noise, both_noise, old_noise / both_noise);
      std::fflush(stdout);
    }
    render::RenderSettings uniform_both = both;
    uniform_both.grazing_samples = 1.0;
    render::RenderSettings independent = stratified;
    independent.sampler = render::Sampler::independent;
    const std::pair<const char*, const render::RenderSettings*> timings[] = {
        {"independent", &independent},
        {"stratified", &stratified},
        {"light and lobe, spp in every pixel", &uniform_both},
        {"light and lobe, grazing samples (the default)", &both}};
    for (const auto& [label, timing] : timings) {
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();  // CPU time of all threads: less sensitive to the load
      render::RenderStats stats;
      (void)render::render(scene, atlas::ModelMaterial(model, model.material_weights(model.index_of(argv[7]))), *timing,
                           null_progress(), &stats);
      const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      std::printf("%s: one render %.2f s wall, %.2f s CPU (%.2f M camera samples per CPU second)\n", label, sec, cpu,
                  static_cast<double>(stats.camera_samples) / cpu * 1e-6);
    }
    render::RenderSettings basis_settings;  // the defaults (light and lobe, grazing samples)
    basis_settings.width = basis_settings.height = std::stoi(argv[5]);
    basis_settings.spp = std::stoi(argv[6]);
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const render::ImageBasis basis = atlas::render_basis(model, scene, basis_settings);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("preview basis %dx%d, %d spp, n = %d (+ mean): %.1f s wall, %.1f s CPU\n", basis.width(),
                basis.height(), basis_settings.spp, basis.count(), sec,
                static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_preview_noise: %s\n", e.what());
    return 1;
  }
}
