#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "formats/spectral_rgb.h"

namespace matlas {
namespace {

std::vector<float> even_wavelengths(int count) {
  std::vector<float> w(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) w[static_cast<std::size_t>(k)] = static_cast<float>(360.0 + 470.0 * k / (count - 1));
  return w;
}

TEST(SpectralRgb, ColourMatchingFunctionsPeakWhereTheCieOnesDo) {
  // Independent anchors of CIE 1931: y peaks at 555 nm (1.0), x's main lobe near 600 nm (1.06),
  // z near 445 nm (1.78); all nearly vanish at 360 and 830 nm.
  const auto y555 = cie_xyz(555.0), x600 = cie_xyz(600.0), z445 = cie_xyz(445.0);
  EXPECT_NEAR(y555[1], 1.0, 0.03);
  EXPECT_NEAR(x600[0], 1.06, 0.05);
  EXPECT_NEAR(z445[2], 1.78, 0.1);
  for (double l : {360.0, 830.0})
    for (double v : cie_xyz(l)) EXPECT_LT(std::abs(v), 0.01) << l;
}

TEST(SpectralRgb, AConstantSpectrumReducesToGrey) {
  const std::vector<float> w = even_wavelengths(16);
  const SpectralUpsampler up(w);
  const std::vector<float> flat(16, 0.37f);
  for (double c : up.reduce(flat.data())) EXPECT_NEAR(c, 0.37, 1e-6);
  // A spectrum that rises with wavelength is red, one that falls is blue.
  std::vector<float> rising(16), falling(16);
  for (std::size_t k = 0; k < 16; ++k) rising[k] = static_cast<float>(k) / 15.0f, falling[k] = 1.0f - rising[k];
  const auto r = up.reduce(rising.data()), b = up.reduce(falling.data());
  EXPECT_GT(r[0], r[2]);
  EXPECT_GT(b[2], b[0]);
}

TEST(SpectralRgb, SpectraFittedToColoursReduceBackToThem) {
  const SpectralUpsampler up(even_wavelengths(16));
  const std::vector<std::array<double, 3>> colours{
      {0.7, 0.5, 0.3}, {0.2, 0.4, 0.8}, {0.05, 0.6, 0.1}, {0.9, 0.9, 0.9}, {0.01, 0.01, 0.012}, {12.0, 7.0, 3.0}};
  for (const auto& rgb : colours) {
    SCOPED_TRACE(::testing::PrintToString(rgb));
    const SpectralUpsampler::Fit f = up.fit(rgb);
    std::vector<float> s(16);
    up.spectrum(f, s.data());
    const double top = std::max({rgb[0], rgb[1], rgb[2]});
    for (float v : s) {
      EXPECT_GE(v, 0.0f);
      EXPECT_LE(v, 2.0 * top + 1e-6);  // the model's range: (0, scale)
    }
    const auto back = up.reduce(s.data());
    for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(back[c], rgb[c], 1e-5 * top);
    EXPECT_LT(f.error, 1e-5);
    // From a neighbour's coefficients the same spectrum (the fit is the model's unique match).
    const SpectralUpsampler::Fit warm = up.fit(rgb, &f);
    std::vector<float> s2(16);
    up.spectrum(warm, s2.data());
    for (std::size_t k = 0; k < 16; ++k) EXPECT_NEAR(s2[k], s[k], 1e-4 * top);
  }
  // Grey is a constant spectrum; black is zero.
  std::vector<float> s(16);
  up.spectrum(up.fit({0.3, 0.3, 0.3}), s.data());
  for (float v : s) EXPECT_NEAR(v, 0.3, 1e-5);
  const SpectralUpsampler::Fit black = up.fit({0.0, -1.0, 0.0});
  EXPECT_EQ(black.scale, 0.0);
  up.spectrum(black, s.data());
  for (float v : s) EXPECT_EQ(v, 0.0f);
}

TEST(SpectralRgb, ThePrimariesAndSecondariesAreReachedAndTheErrorIsTheResidual) {
  // Every sRGB colour lies inside the spectral locus, and the model has twice the largest
  // channel of headroom: the primaries and secondaries are reached too. The reported error is
  // the distance of the reduced spectrum from the (clamped) colour, relative to its largest
  // channel.
  const SpectralUpsampler up(even_wavelengths(16));
  for (const std::array<double, 3>& rgb : std::vector<std::array<double, 3>>{
           {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0}, {2, -1, 0}}) {
    SCOPED_TRACE(::testing::PrintToString(rgb));
    const SpectralUpsampler::Fit f = up.fit(rgb);
    std::vector<float> s(16);
    up.spectrum(f, s.data());
    const auto back = up.reduce(s.data());
    const double top = std::max({rgb[0], rgb[1], rgb[2]});
    double distance = 0;
    for (std::size_t c = 0; c < 3; ++c) distance += std::pow(back[c] - std::max(0.0, rgb[c]), 2);
    distance = std::sqrt(distance) / top;
    EXPECT_LT(distance, 1e-5);
    EXPECT_NEAR(f.error, distance, 1e-5);  // float32 spectrum against the double residual
  }
}

TEST(SpectralRgb, AFarNeighboursStartDoesNotStallTheFit) {
  // The writer starts each sample's fit from its neighbour's. Fitted reflectance samples can sit
  // beside very different ones (a channel held at 0 over a highlight, next to grey): from a
  // saturated neighbour's coefficients the sigmoid is flat and the steps stall, which left 20 % of
  // a spectral file's samples off (up to 100 %). Every colour is reached from any start.
  const SpectralUpsampler up(even_wavelengths(12));
  std::vector<SpectralUpsampler::Fit> starts;
  for (const std::array<double, 3>& rgb : std::vector<std::array<double, 3>>{{1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {5, 0.01, 0}})
    starts.push_back(up.fit(rgb));
  SpectralUpsampler::Fit extreme;
  extreme.scale = 1, extreme.coefficients = {4e3, -4e3, 300};
  starts.push_back(extreme);
  for (const SpectralUpsampler::Fit& start : starts)
    for (const std::array<double, 3>& rgb : std::vector<std::array<double, 3>>{{0.3, 0.3, 0.3}, {0.02, 0.5, 0.9}, {0.8, 0.1, 0.05}}) {
      SCOPED_TRACE(::testing::PrintToString(rgb));
      EXPECT_LT(up.fit(rgb, &start).error, 1e-5);
    }
}

TEST(SpectralRgb, ARendererInterpolatingTheSamplesSeesTheSameColour) {
  // Spectral renderers (pbrt-v4, Mitsuba 3) sample wavelengths continuously and interpolate a
  // file's spectra linearly: the fitted samples, interpolated onto a 1 nm grid and reduced there,
  // give the colour (with samples reduced at their own wavelengths only, 16 of them were 3 % off).
  std::vector<float> fine;
  for (int l = 360; l <= 830; ++l) fine.push_back(static_cast<float>(l));
  const auto weights = spectral_to_rgb_weights(fine);
  for (int count : {12, 16, 24}) {
    const SpectralUpsampler up(even_wavelengths(count));
    for (const std::array<double, 3>& rgb : std::vector<std::array<double, 3>>{{0.05, 0.6, 0.1}, {0.8, 0.1, 0.05}, {0.2, 0.4, 0.8}}) {
      SCOPED_TRACE(::testing::PrintToString(rgb) + " at " + std::to_string(count) + " wavelengths");
      std::vector<float> s(static_cast<std::size_t>(count));
      up.spectrum(up.fit(rgb), s.data());
      std::array<double, 3> seen{0, 0, 0};
      for (std::size_t i = 0; i < fine.size(); ++i) {
        const double x = (fine[i] - 360.0) / 470.0 * (count - 1);
        const auto k = static_cast<std::size_t>(std::min<double>(count - 2, std::floor(x)));
        const double a = x - static_cast<double>(k), v = (1 - a) * s[k] + a * s[k + 1];
        for (std::size_t c = 0; c < 3; ++c) seen[c] += weights[i][c] * v;
      }
      for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(seen[c], rgb[c], 2e-4);
    }
  }
}

TEST(SpectralRgb, WeightsOfAnyFiniteWavelengthsAreFinite) {
  // A file's wavelengths may be anything finite (found by fuzzing: a span of 1e31 nm once asked
  // for 1e31 integration steps). Outside 300-900 nm the colour-matching functions vanish.
  for (const std::vector<float>& w : std::vector<std::vector<float>>{{1.0f, 1e31f, 2e31f}, {400.0f, 1e31f}, {-1e30f, 550.0f, 3e38f}}) {
    for (const auto& row : spectral_to_rgb_weights(w))
      for (double v : row) EXPECT_TRUE(std::isfinite(v));
  }
  for (const auto& row : spectral_to_rgb_weights({1e20f, 2e20f}))
    for (double v : row) EXPECT_EQ(v, 0.0);  // nothing visible: no colour
}

TEST(SpectralRgb, RejectsTooFewOrUnorderedWavelengths) {
  EXPECT_THROW(SpectralUpsampler({400.0f, 500.0f}), Error);
  EXPECT_THROW(SpectralUpsampler({400.0f, 500.0f, 500.0f}), Error);
  EXPECT_NO_THROW(SpectralUpsampler({400.0f, 500.0f, 600.0f}));
}

}  // namespace
}  // namespace matlas
