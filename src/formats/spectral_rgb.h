#pragma once
// Spectra and RGB, both ways, as the RGL `.bsdf` format needs them (docs/EXPORT.md, "Spectral
// files"): a sampled spectrum reduced to linear sRGB with the CIE 1931 colour-matching functions
// (balanced: a constant spectrum gives equal RGB), and an RGB value raised to a smooth spectrum by
// Jakob & Hanika's sigmoid-polynomial model (2019): s(t) = scale sigma(c0 t^2 + c1 t + c2), t the
// wavelength mapped to [0, 1], sigma(z) = 1/2 + z / (2 sqrt(1 + z^2)), fitted so that the
// spectrum's reduction is the RGB value (for values above 1, as BRDF samples are, the RGB is
// divided by twice its largest channel first and the spectrum multiplied back, as Mitsuba 3 does
// for unbounded spectra).
#include <array>
#include <vector>

namespace matlas {

/// CIE 1931 x, y, z colour-matching functions at a wavelength in nm (the multi-lobe fit of Wyman,
/// Sloan & Shirley 2013).
std::array<double, 3> cie_xyz(double nm);

/// Per wavelength (nm, increasing): the weights that reduce a spectrum sampled there to linear
/// sRGB, sum_k w[k][c] s_k: the spectrum taken as linear between its samples (as spectral
/// renderers interpolate a file's spectra) and zero outside them, integrated against the
/// colour-matching functions, normalised so that a constant spectrum gives that constant in
/// every channel.
std::vector<std::array<double, 3>> spectral_to_rgb_weights(const std::vector<float>& wavelengths);

/// Fits sigmoid-polynomial spectra to RGB values at fixed wavelengths.
class SpectralUpsampler {
public:
  /// Throws matlas::Error unless at least 3 wavelengths, strictly increasing.
  explicit SpectralUpsampler(std::vector<float> wavelengths);

  const std::vector<float>& wavelengths() const { return wavelengths_; }

  struct Fit {
    std::array<double, 3> coefficients{0, 0, 0};  ///< c0, c1, c2 (of the scaled RGB)
    double scale = 0;                             ///< 2 max(rgb); 0 for black
    double error = 0;  ///< |reduce(spectrum) - rgb| / max(rgb): 0 when the model reaches the colour
  };

  /// The fit for rgb (negative channels are taken as 0), by Levenberg-Marquardt from `start`'s
  /// coefficients (a neighbour's fit converges in a few steps) or from grey; when the start's fit
  /// does not reach the colour (a far neighbour's can stall), again from grey, the better kept.
  Fit fit(const std::array<double, 3>& rgb, const Fit* start = nullptr) const;

  /// The fitted spectrum at the wavelengths (wavelengths().size() values).
  void spectrum(const Fit& f, float* out) const;

  /// sum_k w[k][c] s_k for a spectrum at the wavelengths: what a reader of the file sees.
  std::array<double, 3> reduce(const float* spectrum) const;

private:
  std::vector<float> wavelengths_;
  std::vector<double> t_;                        // wavelengths mapped to [0, 1]
  std::vector<std::array<double, 3>> weights_;  // spectral_to_rgb_weights
};

}  // namespace matlas
