// The sampling mixture fitted to a database (atlas/sampling_fit.h): lobe widths read from
// analytic conductors of known width, an unbiased furnace with the fitted mixture, and lower noise
// than the former fixed mixture on a chrome-like material at equal samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>

#include "atlas/sampling_fit.h"
#include "brdf/analytic.h"
#include "render/material.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "render/scene.h"

namespace matlas::atlas {
namespace {

using render::FunctionMaterial;
using render::RenderSettings;

FunctionMaterial conductor(double alpha) {
  return FunctionMaterial([g = GgxConductor{Rgb(0.95, 0.93, 0.9), alpha}](const Vec3& wi, const Vec3& wo) {
    return g(wi, wo);
  });
}

FunctionMaterial plastic(double alpha) {
  return FunctionMaterial([p = RoughPlastic{Rgb(0.3, 0.1, 0.05), alpha}](const Vec3& wi, const Vec3& wo) {
    return p(wi, wo);
  });
}

/// Relative RMS difference of two seeds over the pixels fully covered by the sphere.
double seed_noise(const render::Scene& scene, const render::Material& m, RenderSettings s) {
  const std::vector<float> coverage = render::object_coverage(scene, s);
  s.seed = 3;
  const Image a = render::render(scene, m, s);
  s.seed = 4;
  const Image b = render::render(scene, m, s);
  double d = 0, sum = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] == 1.0f)
      for (std::size_t c = 0; c < 3; ++c) {
        const double x = a.rgb[3 * p + c], y = b.rgb[3 * p + c];
        d += (x - y) * (x - y);
        sum += 0.25 * (x + y) * (x + y);
      }
  return std::sqrt(d / sum);
}

TEST(SamplingFit, LobeWidthsOfAnalyticConductorsAreTheirAlphas) {
  const FunctionMaterial c1 = conductor(0.004), c2 = conductor(0.03);
  const render::MaterialList bank({&c1, &c2});
  const std::vector<double> w = specular_lobe_widths(bank);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NEAR(w[0] / 0.004, 1.0, 0.25);
  EXPECT_NEAR(w[1] / 0.03, 1.0, 0.25);
  // The fitted mixture: GGX lobes between the two widths' ends, and a tabulated lobe.
  const render::SamplingMixture m = fit_sampling_mixture(bank);
  ASSERT_FALSE(m.lobes.empty());
  EXPECT_LT(m.lobes.front().first, 0.006);
  EXPECT_GT(m.lobes.back().first, 0.02);
  EXPECT_GT(m.tabulated, 0.0);
  // Nothing glossy: the default mixture.
  const FunctionMaterial lambert([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.5 / kPi); });
  const render::MaterialList matte({&lambert});
  EXPECT_EQ(specular_lobe_widths(matte)[0], 0.0);
  EXPECT_EQ(fit_sampling_mixture(matte).lobes, render::SamplingMixture::preview_default().lobes);
  EXPECT_EQ(fit_sampling_mixture(matte).tabulated, 0.0);
}

TEST(SamplingFit, FurnaceWithTheFittedMixtureEqualsTheAlbedo) {
  // A white Lambertian in a uniform environment of radiance 1 reflects exactly 1 everywhere.
  const FunctionMaterial c1 = conductor(0.004), p1 = plastic(0.1);
  const render::MaterialList bank({&c1, &p1});
  render::SceneDescription d;
  d.constant_radiance = Rgb::Constant(1.0);
  const render::Scene scene(d);
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = 256;
  s.mixture = fit_sampling_mixture(bank);
  const FunctionMaterial white([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(1.0 / kPi); });
  const Image image = render::render(scene, white, s);
  const std::vector<float> coverage = render::object_coverage(scene, s);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::covered_mean(image, coverage, c), 1.0, 0.01);
}

/// A small glossy database (a chrome-like and a glossy conductor, a plastic, a Lambertian) under the
/// synthetic sky with its small bright sun.
struct GlossyDatabase {
  FunctionMaterial chrome = conductor(0.004), gold = conductor(0.03), glossy_plastic = plastic(0.1);
  FunctionMaterial lambert{[](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.5 / kPi); }};
  render::MaterialList bank{{&chrome, &gold, &glossy_plastic, &lambert}};
  render::Scene scene{render::SceneDescription{}, std::nullopt, render::Environment(test::synthetic_environment())};
};

TEST(SamplingFit, ChromeIsFarLessNoisyWithTheFittedMixtureAndTheStratifiedSampler) {
  // A chrome-like conductor under a sky with a small bright sun, 32x32, 32 spp: the previews'
  // former sampling (fixed mixture, independent numbers per sample), the former mixture with the
  // stratified sampler, and the mixture fitted to the database for that sampler (with its
  // sharpest lobe). Measured: 0.87, 0.83 and 0.23; asserted: the fitted mixture at
  // least 25 % below the former one with the same sampler, and 3x below the former sampling.
  const GlossyDatabase db;
  const FunctionMaterial& chrome = db.chrome;
  const render::MaterialList& bank = db.bank;
  const render::Scene& scene = db.scene;
  RenderSettings former_mixture;
  former_mixture.width = former_mixture.height = 32;
  former_mixture.spp = 32;
  former_mixture.sampler = render::Sampler::stratified;
  former_mixture.grazing_samples = 1.0;  // spp in every pixel, as the former sampling
  RenderSettings former = former_mixture, fitted = former_mixture;
  former.sampler = render::Sampler::independent;
  fitted.mixture = fit_sampling_mixture(bank);
  const double former_noise = seed_noise(scene, chrome, former);
  const double mixture_noise = seed_noise(scene, chrome, former_mixture), new_noise = seed_noise(scene, chrome, fitted);
  RecordProperty("former", std::to_string(former_noise));
  RecordProperty("former_mixture_stratified", std::to_string(mixture_noise));
  RecordProperty("fitted_stratified", std::to_string(new_noise));
  EXPECT_LT(new_noise, 0.75 * mixture_noise) << "former mixture " << mixture_noise << ", fitted " << new_noise;
  EXPECT_LT(new_noise, former_noise / 3.0) << "former " << former_noise << ", now " << new_noise;
  // The sharpest lobe sits at the chrome's width.
  EXPECT_NEAR(fitted.mixture.lobes.front().first / 0.004, 1.0, 0.25);
}

TEST(SamplingFit, TheDefaultLightAndLobeSamplerIsLessNoisyAtEqualSamples) {
  // The same database and sky as above, 32x32, 32 spp: the stratified sampler with the mixture
  // fitted for it and spp in every pixel (the former default) against the default: the
  // light-and-lobe sampler with the mixture fitted for it (model_render_settings' choice) and the
  // samples following the view angle, on the chrome, the glossy conductor and the plastic.
  // Measured 2.43x, 1.23x and 1.40x lower relative RMS; asserted 1.8x, 1.1x and 1.2x.
  const GlossyDatabase db;
  const FunctionMaterial &chrome = db.chrome, &gold = db.gold, &p1 = db.glossy_plastic;
  const render::MaterialList& bank = db.bank;
  const render::Scene& scene = db.scene;
  RenderSettings light_and_lobe;
  light_and_lobe.width = light_and_lobe.height = 32;
  light_and_lobe.spp = 32;
  ASSERT_EQ(light_and_lobe.sampler, render::Sampler::light_and_lobe);  // the default
  RenderSettings stratified = light_and_lobe;
  stratified.sampler = render::Sampler::stratified;
  stratified.grazing_samples = 1.0;  // the former default
  stratified.mixture = fit_sampling_mixture(bank, SamplingFitOptions::for_sampler(stratified.sampler));
  light_and_lobe.mixture = fit_sampling_mixture(bank, SamplingFitOptions::for_sampler(light_and_lobe.sampler));
  EXPECT_GT(light_and_lobe.mixture.lobes.front().second, stratified.mixture.lobes.front().second);
  for (const auto& [name, material, gain] :
       {std::tuple{"chrome", &chrome, 1.8}, std::tuple{"glossy conductor", &gold, 1.1},
        std::tuple{"plastic", &p1, 1.2}}) {
    const double a = seed_noise(scene, *material, stratified), b = seed_noise(scene, *material, light_and_lobe);
    RecordProperty(std::string(name) + "_stratified", std::to_string(a));
    RecordProperty(std::string(name) + "_light_and_lobe", std::to_string(b));
    std::printf("%s: stratified %.4f, light and lobe %.4f (%.2fx)\n", name, a, b, a / b);
    EXPECT_LT(b * gain, a) << name << ": stratified " << a << ", light and lobe " << b;
  }
}

TEST(SamplingFit, TheDefensiveMixtureHasTheMeanDensityOfItsTwoMixtures) {
  render::SamplingMixture a(0.5, 0.1, {{0.02, 0.3}});
  std::vector<double> pa(90, 0.0), pb(90, 0.0);
  for (std::size_t i = 0; i < 90; ++i) pa[i] = std::exp(-0.2 * static_cast<double>(i)), pb[i] = 1.0 + 0.01 * static_cast<double>(i);
  a.set_profile(pa, 0.2);
  render::SamplingMixture b(0.4, 0.05, {{0.1, 0.2}, {0.4, 0.1}});
  b.set_profile(pb, 0.25);
  const render::SamplingMixture m = defensive_mixture(a, b);
  EXPECT_NO_THROW(m.validate());
  EXPECT_NEAR(m.environment_probability(), 0.5 * (a.environment_probability() + b.environment_probability()), 1e-12);
  ASSERT_EQ(m.lobes.size(), 3u);
  // local_pdf is each mixture's lobe density weighted by its normalised probabilities: the
  // defensive mixture's is their mean, at any pair of directions.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const auto dir = [&] {
      const double z = 0.02 + 0.98 * u(rng), phi = 2 * 3.14159265358979 * u(rng), r = std::sqrt(1 - z * z);
      return Vec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    const Vec3 wo = dir(), wi = dir();
    EXPECT_NEAR(m.local_pdf(wo, wi), 0.5 * (a.local_pdf(wo, wi) + b.local_pdf(wo, wi)),
                1e-9 * (1 + a.local_pdf(wo, wi) + b.local_pdf(wo, wi)));
  }
}

}  // namespace
}  // namespace matlas::atlas
