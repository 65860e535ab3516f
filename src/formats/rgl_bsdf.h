#pragma once
// RGL measured BSDFs (Dupuy & Jakob 2018, "An Adaptive Parameterization for Efficient Material
// Acquisition and Rendering"; the `.bsdf` files of the RGL material database, which Mitsuba's
// `measured` plugin and pbrt-v4 render), and their resampling onto the MERL grid.
//
// A `.bsdf` file is a tensor file (formats/tensor_file.h) with the fields
//   description  uint8 [n]                      free text
//   theta_i      float32 [Nt]                   incident elevations of the measurement (radians)
//   phi_i        float32 [Np]                   incident azimuths (Np <= 2: isotropic)
//   ndf          float32 [Ny, Nx]               microfacet distribution D on (theta, phi) coordinates
//   sigma        float32 [Ny, Nx]               projected microfacet area sigma(wi)
//   vndf         float32 [Np, Nt, My, Mx]        visible-normal distribution per incident direction
//   luminance    float32 [Np, Nt, Ry, Rx]        used for importance sampling only (sample(), pdf())
//   rgb          float32 [Np, Nt, 3, Ry, Rx]     reflectance in the VNDF's warped coordinates, or
//   spectra      float32 [Np, Nt, L, Ry, Rx] with wavelengths float32 [L] (nm)
//   jacobian     uint8 [1]                      1: apply D / (4 sigma)
// (a `valid` mask, a `version` field and others may be present and are not needed).
//
// Evaluation follows the reference implementation: with theta = elevation, the unit coordinates
// are u(theta) = sqrt(2 theta / pi) and u(phi) = (phi + pi) / (2 pi); the half vector's
// coordinates (its azimuth taken relative to phi_i for isotropic materials) go through the
// inverse of the VNDF warp at the incident direction, the reflectance table is interpolated
// there, and multiplied by D(h) / (4 sigma(wi)) when `jacobian` is set. The result is
// f(wi, wo) cos(theta_o); eval() divides the cosine out to give the BRDF f. As RGL's loader (and
// so Mitsuba) does, the interpolated reflectance is clipped at 0 before the Jacobian: saturated
// colours and noise leave negative samples in the files (18 % of iris_purple_gem's values at
// random directions), and a renderer never sees them.
//
// Importance sampling (sample(), pdf()) follows Mitsuba's `measured` plugin: a point of the
// reflectance's unit square from the luminance warp (when the file has a usable `luminance`),
// through the VNDF's sample warp to the half vector's coordinates, reflected about it; the
// density is vndf_pdf * luminance_pdf / (2 pi^2 u sin(theta_m) * 4 (wi.m)).
//
// Spectral files are reduced to RGB when read (linear sRGB primaries, CIE 1931 observer through
// the analytic fit of Wyman, Sloan and Shirley 2013, balanced so that a flat spectrum of
// reflectance 1 is RGB (1, 1, 1)); interpolation is linear in the data, so this commutes with
// the model's interpolation.
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "brdf/brdf_table.h"
#include "brdf/types.h"
#include "formats/rgl_warp.h"
#include "formats/tensor_file.h"

namespace matlas {

class RglBsdf {
public:
  /// Reads and validates a `.bsdf` file; every problem is a matlas::Error naming the file.
  static RglBsdf read(const std::filesystem::path& path);
  /// From an already parsed tensor file (its path names errors).
  explicit RglBsdf(const TensorFile& file);
  /// The same, freeing each field's bytes once converted (read() peaks at about twice the
  /// reflectance field's size instead of five times).
  explicit RglBsdf(TensorFile&& file);

  const std::filesystem::path& path() const { return path_; }
  const std::string& description() const { return description_; }
  bool isotropic() const { return isotropic_; }
  /// Spectral in the file (then reduced to RGB here); `wavelength_count` samples.
  bool spectral() const { return wavelength_count_ > 0; }
  std::size_t wavelength_count() const { return wavelength_count_; }
  bool jacobian() const { return jacobian_; }
  std::size_t theta_i_count() const { return theta_i_.size(); }
  /// The incident elevations (radians), ascending.
  const std::vector<float>& theta_i() const { return theta_i_; }
  std::size_t phi_i_count() const { return phi_i_.size(); }
  /// One line: "isotropic, RGB, 8 x 1 incident directions, VNDF 128x128, reflectance 32x32".
  std::string summary() const;

  /// f(wi, wo) cos(theta_o) as Mitsuba's measured BSDF evaluates it (0 when either direction is
  /// below the horizon, or not finite). Directions are in the local frame (normal +z; normalised
  /// here); wi is the direction of the light, wo the view.
  Rgb eval_cosine(const Vec3& wi, const Vec3& wo) const;
  /// Where eval_cosine looks the reflectance up: the point `at` of the reflectance's unit square,
  /// the blend of incident slices (channel c of blended slice s is the reflectance table's slice
  /// 3 s + c), and the factor that multiplies the interpolated value after its clip at 0 (D(m) /
  /// (4 sigma(wi)), 1 without the Jacobian). eval_cosine(wi, wo)[c] = scale * max(0, the
  /// reflectance interpolated at `at` and blended): linear in the samples before the clip.
  /// `valid` is false where eval_cosine is 0 whatever the samples (a direction below the horizon).
  struct ReflectanceLookup {
    bool valid = false;
    std::array<double, 2> at{0.0, 0.0};
    ParamBlend blend;
    double scale = 0;
  };
  ReflectanceLookup reflectance_lookup(const Vec3& wi, const Vec3& wo) const;
  /// The cell of the reflectance table's grid that a lookup interpolates (its corners' index in
  /// every slice: py * reflectance_nx() + px).
  RglWarp2D::Cell reflectance_cell(const ReflectanceLookup& l) const { return rgb_.cell(l.at[0], l.at[1]); }
  /// The reflectance table's grid (nx, ny per slice).
  std::size_t reflectance_nx() const { return rgb_.nx(); }
  std::size_t reflectance_ny() const { return rgb_.ny(); }

  /// The BRDF f(wi, wo) (1/sr): eval_cosine / cos(theta_o).
  Rgb eval(const Vec3& wi, const Vec3& wo) const;
  /// The reciprocal BRDF closest to the model's two measurements of this pair: with E1 =
  /// eval_cosine(wi, wo) ~ f cos(theta_o) and E2 = eval_cosine(wo, wi) ~ f cos(theta_i), the
  /// least-squares f = (cos_o E1 + cos_i E2) / (cos_i^2 + cos_o^2). It is the plain average of
  /// the two orders when the angles are equal, and near the horizon it leans on the order whose
  /// cosine is not small (dividing a grazing measurement by its small cosine amplifies its
  /// noise without bound). Symmetric in (wi, wo): what a MERL table can hold.
  Rgb eval_reciprocal(const Vec3& wi, const Vec3& wo) const;

  /// Reflectance samples of the file (per channel, RGB after reduction) below 0, and all of them.
  std::size_t negative_samples() const { return negative_samples_; }
  std::size_t reflectance_samples() const { return rgb_.slices() * rgb_.nx() * rgb_.ny(); }
  /// True when the file's `luminance` field is present, of the reflectance's shape, and usable
  /// as a sampling density (positive integral for every incident direction).
  bool has_luminance() const { return has_luminance_; }

  /// A direction drawn for the first direction wi (the one whose elevation indexes the tables,
  /// the view in Mitsuba's convention) from uniform (u1, u2), as Mitsuba samples the file.
  struct Sample {
    Vec3 wo = Vec3::Zero();
    double pdf = 0;  ///< solid-angle density of wo; 0 when the sample failed (wo below the horizon)
  };
  Sample sample(const Vec3& wi, double u1, double u2) const;
  /// The density of sample() at wo.
  double pdf(const Vec3& wi, const Vec3& wo) const;

private:
  RglBsdf() = default;
  /// The constructors' work; `owned` is the file when its fields' bytes may be freed.
  void load(const TensorFile& file, TensorFile* owned);

  std::filesystem::path path_;
  std::string description_;
  bool isotropic_ = true;
  bool jacobian_ = true;
  int reduction_ = 0;  ///< symmetry folding of anisotropic measurements (2 or 4), as Mitsuba
  std::size_t wavelength_count_ = 0;
  std::vector<float> theta_i_, phi_i_;
  RglWarp2D ndf_, sigma_, vndf_;
  RglWarp2D rgb_;  ///< slices [phi_i][theta_i][channel]
  RglWarp2D luminance_;  ///< with CDFs, when has_luminance_
  bool has_luminance_ = false;
  std::size_t negative_samples_ = 0;
};

/// What resampling onto the MERL grid did.
struct RglResampling {
  std::size_t bins = 0;            ///< bins of the grid
  std::size_t measured_bins = 0;   ///< bins with both directions above the horizon
  std::size_t missing_bins = 0;    ///< below the horizon: stored as -1 (missing), as MERL does
  /// Reciprocal values below 0 stored as 0 (none since evaluation clips at 0, as RGL's loader;
  /// RglBsdf::negative_samples() counts the file's negative samples).
  std::size_t clamped_values = 0;
  /// Non-reciprocity of the model at the bin centres: sum |f(wi,wo) - f(wo,wi)| over sum of
  /// (f(wi,wo) + f(wo,wi)) / 2, weighted by cos(theta_i) cos(theta_o), over channels. The table
  /// holds RglBsdf::eval_reciprocal (a MERL table is reciprocal by construction).
  double reciprocity_error = 0;
  Rgb max_value = Rgb::Zero();     ///< largest physical value per channel
};

/// Resamples an isotropic RGL BSDF at the centres of the MERL grid's bins (theta_h =
/// ((i+0.5)/N)^2 90 deg, theta_d = (j+0.5)/N 90 deg, phi_d = (k+0.5)/N 180 deg), RGB, bins with
/// a direction below the horizon marked missing. An anisotropic material is refused with
/// "anisotropic, not supported yet". Parallel over the grid.
BrdfTable resample_to_merl(const RglBsdf& bsdf, RglResampling* report = nullptr, const MerlDims& dims = {});

/// True for a path whose extension is `.bsdf`.
bool is_rgl_path(const std::filesystem::path& path);

/// Reads a MERL `.binary` file, or an RGL `.bsdf` file resampled onto the standard MERL grid.
BrdfTable read_brdf(const std::filesystem::path& path);

}  // namespace matlas
