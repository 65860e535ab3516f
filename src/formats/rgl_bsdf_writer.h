#pragma once
// Writing a MERL-grid table as an isotropic RGL `.bsdf` file (Dupuy & Jakob 2018), the format
// Mitsuba 3's `measured` plugin and pbrt-v4 read, with the fields and layout of the RGL
// database's own isotropic RGB files (docs/EXPORT.md):
//
//   version      uint8 [2]                 1, 0
//   description  uint8 [n]                 free text
//   phi_i        float32 [1]               0 (isotropic)
//   theta_i      float32 [Nt]              incident elevations over [0, 90 deg], denser at grazing
//   sigma        float32 [2, Ns]           projected area sigma(theta_i) on u = sqrt(2 theta / pi)
//   ndf          float32 [2, Nd]           D(theta_m) on u (both rows equal: no azimuth dependence)
//   vndf         float32 [1, Nt, Nv, Nv]   the sample warp of the half vector per incident
//                                          elevation, on the unit square (x: u of theta_m, y: phi_m
//                                          - phi_i): the VNDF D(m) max(0, wi.m) / sigma(wi) times
//                                          the square's Jacobian 2 pi^2 u sin(theta_m), mixed with
//                                          a density 1 / sqrt(u + u0) that keeps samples where the
//                                          table varies faster than the NDF (resolution_mix)
//   luminance    float32 [1, Nt, Nr, Nr]   the luminance of the integrand on the reflectance's
//                                          square (samples times VNDF over warp density): the
//                                          density of the file's importance sampling
//   rgb          float32 [1, Nt, 3, Nr, Nr] f(wi, wo) cos(theta_o) 4 sigma(wi) / D(m) at the
//                                          points of the reflectance's unit square, mapped to
//                                          half vectors m by the VNDF's sample warp
//   (spectral files: wavelengths float32 [W] and spectra float32 [1, Nt, W, Nr, Nr] instead)
//   jacobian     uint8 [1]                 1
//   valid        uint8 [ceil(Nt Nr Nr / 8)] bit per sample (first sample in the high bit): wo
//                                          above the horizon
//
// The NDF comes from the table's back-scattering by power iterations (brdf/ndf_extraction.h).
// Every warp is built from the float32 values written, through the same code the reader uses
// (formats/rgl_warp.h), so the samples sit exactly where the reader looks them up.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "brdf/brdf_table.h"
#include "brdf/ndf_extraction.h"
#include "formats/rgl_sample_fit.h"
#include "formats/tensor_file.h"

namespace matlas {

/// The wavelengths of `matlas export --format bsdf-spectral` and the server's spectral download:
/// from 12 on a renderer interpolating the spectra reproduces the colours within 0.01 %
/// (formats/spectral_rgb.h).
inline constexpr int kSpectralExportWavelengths = 12;

struct RglExportOptions {
  int theta_i = 32;          ///< incident elevations
  double theta_max_deg = 90.0;  ///< the last one (the reader and Mitsuba clamp beyond it)
  /// Spacing of the elevations: theta_max ((1 - g) x + g sin(pi x / 2)) at x = k / (Nt - 1),
  /// denser towards grazing incidence for g > 0.
  double grazing_refinement = 0.8;
  int vndf_resolution = 96;   ///< VNDF grid per incident elevation
  int rgb_resolution = 80;    ///< reflectance grid per incident elevation
  int sigma_resolution = 128;
  /// Weight of the resolution density in the warp written as `vndf` (the rest is the VNDF).
  double resolution_mix = 0.5;
  /// 0: an RGB file (`rgb`). Else a spectral file (`wavelengths`, `spectra` [1, Nt, W, Nr, Nr]
  /// instead of `rgb`, the form pbrt-v4 reads) with this many wavelengths evenly spaced over
  /// 360-830 nm, each sample's RGB raised to a smooth spectrum (formats/spectral_rgb.h).
  int wavelengths = 0;
  NdfExtractionOptions ndf;   ///< D's nodes and iterations
  /// The reflectance samples fitted to the table's bin centres in least squares
  /// (formats/rgl_sample_fit.h); iterations 0 keeps the samples taken at the nodes.
  RglSampleFitOptions fit;
  std::string description;    ///< written into the file
};

struct RglExportReport {
  NdfExtractionReport ndf;
  RglSampleFitReport fit;           ///< the samples' least-squares fit (iterations 0: none)
  std::size_t samples = 0;          ///< reflectance samples (per channel)
  std::size_t below_horizon = 0;    ///< samples whose wo is below the horizon (written as 0, invalid)
  double largest_value = 0;         ///< largest reflectance sample
  /// Spectral files: |RGB of the spectrum - RGB of the sample| / its largest channel, RMS and
  /// largest over the samples (what the spectral model cannot reach: very saturated colours).
  double spectral_error_rms = 0, spectral_error_max = 0;
  std::size_t bytes = 0;            ///< size of the file
};

/// The fields of the `.bsdf` file of `table` (its missing bins read as 0, interpolated by
/// BrdfTable::lookup_smooth).
std::vector<TensorField> rgl_fields_from_table(const BrdfTable& table, const RglExportOptions& options = {},
                                               RglExportReport* report = nullptr);

/// Writes the file atomically (formats/tensor_file.h's write_tensor_file).
void write_rgl_bsdf(const std::filesystem::path& path, const BrdfTable& table, const RglExportOptions& options = {},
                    RglExportReport* report = nullptr);

}  // namespace matlas
