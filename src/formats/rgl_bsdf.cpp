#include "formats/rgl_bsdf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

#include "core/error.h"
#include "core/parallel.h"
#include "formats/merl_file.h"
#include "formats/spectral_rgb.h"

namespace matlas {

namespace fs = std::filesystem;

namespace {

constexpr const char* kWhat = "RGL measured BSDF (.bsdf)";

/// The float32 values of a field after checking its rank, dtype and that every value is finite.
/// With `owned` (the file, when the reader owns it), the field's bytes are freed once converted.
std::vector<float> floats(const TensorFile& file, const TensorField& f, std::size_t rank, TensorFile* owned) {
  if (f.dtype != TensorType::Float32 || f.shape.size() != rank)
    throw file_error(file.path(), "field '" + f.name + "' is " + f.describe() + ", expected float32 of rank " +
                                      std::to_string(rank));
  std::vector<float> v(f.count());
  if (!v.empty()) std::memcpy(v.data(), f.data.data(), v.size() * sizeof(float));
  if (owned) owned->drop_data(f.name);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw file_error(file.path(), std::string(std::isnan(v[i]) ? "NaN" : "infinite") + " value in field '" + f.name +
                                        "' at element " + std::to_string(i));
  return v;
}

void require(const TensorFile& file, bool ok, const std::string& what) {
  if (!ok) throw file_error(file.path(), "invalid " + std::string(kWhat) + ": " + what);
}

void check_sorted(const TensorFile& file, const std::vector<float>& v, const char* name) {
  for (std::size_t i = 1; i < v.size(); ++i)
    require(file, v[i] > v[i - 1], std::string("field '") + name + "' is not strictly increasing");
}

/// Elevation of a unit vector, accurate near the pole: 2 asin(|d - z| / 2).
double elevation(const Vec3& d) {
  const double dist = std::sqrt(d.x() * d.x() + d.y() * d.y() + (d.z() - 1.0) * (d.z() - 1.0));
  return 2.0 * std::asin(std::clamp(0.5 * dist, -1.0, 1.0));
}
double theta_to_unit(double theta) { return std::sqrt(std::max(theta, 0.0) * (2.0 / kPi)); }
double phi_to_unit(double phi) { return (phi + kPi) * (0.5 / kPi); }
/// a with its sign flipped unless b is negative (Mitsuba's mulsign_neg).
double mulsign_neg(double a, double b) { return std::signbit(b) ? a : -a; }

}  // namespace

RglBsdf RglBsdf::read(const fs::path& path) { return RglBsdf(TensorFile::read(path)); }

RglBsdf::RglBsdf(const TensorFile& file) : path_(file.path()) { load(file, nullptr); }

RglBsdf::RglBsdf(TensorFile&& file) : path_(file.path()) { load(file, &file); }

namespace {

/// Spectral reflectance (per slice, `channels` = wavelengths.size() planes of `grid` values)
/// reduced to RGB planes with the CIE-to-linear-sRGB weights of the wavelengths.
std::vector<float> spectra_to_rgb(const std::vector<float>& spectra, const std::vector<float>& wavelengths,
                                  std::size_t slices, std::size_t grid) {
  const auto weights = spectral_to_rgb_weights(wavelengths);
  const std::size_t channels = wavelengths.size();
  std::vector<float> reduced(slices * 3 * grid, 0.0f);
  for (std::size_t s = 0; s < slices; ++s)
    for (std::size_t l = 0; l < channels; ++l)
      for (std::size_t c = 0; c < 3; ++c) {
        const float* src = spectra.data() + (s * channels + l) * grid;
        float* dst = reduced.data() + (s * 3 + c) * grid;
        const auto w = static_cast<float>(weights[l][c]);
        for (std::size_t k = 0; k < grid; ++k) dst[k] += w * src[k];
      }
  return reduced;
}

/// The file's luminance warp, for sampling only: when it has the reflectance's shape (`shape`:
/// phi_i, theta_i, rows, columns), finite non-negative values and a positive integral in every
/// slice; else none (sampling follows the VNDF alone, as Mitsuba without it). Its bytes in the
/// file are freed when `owned`.
std::optional<RglWarp2D> luminance_warp(const TensorFile& file, TensorFile* owned, const std::array<std::size_t, 4>& shape) {
  const TensorField* lum = file.find("luminance");
  if (!lum || lum->dtype != TensorType::Float32 || lum->shape.size() != 4) return std::nullopt;
  for (std::size_t k = 0; k < 4; ++k)
    if (lum->shape[k] != shape[k]) return std::nullopt;
  std::vector<float> lum_v(lum->count());
  if (!lum_v.empty()) std::memcpy(lum_v.data(), lum->data.data(), lum_v.size() * sizeof(float));
  if (owned) owned->drop_data(lum->name);
  if (!std::all_of(lum_v.begin(), lum_v.end(), [](float v) { return std::isfinite(v) && v >= 0; })) return std::nullopt;
  const std::size_t slices = shape[0] * shape[1];
  RglWarp2D warp(lum_v, shape[3], shape[2], slices, true);
  for (std::size_t sl = 0; sl < slices; ++sl)
    if (!(warp.slice_integral(sl) > 0)) return std::nullopt;
  return warp;
}

}  // namespace

void RglBsdf::load(const TensorFile& file, TensorFile* owned) {
  if (const TensorField* d = file.find("description")) {
    require(file, d->dtype == TensorType::UInt8 && d->shape.size() == 1, "field 'description' is " + d->describe());
    description_.assign(reinterpret_cast<const char*>(d->data.data()), d->data.size());
    while (!description_.empty() && description_.back() == '\0') description_.pop_back();
  }
  theta_i_ = floats(file, file.field("theta_i", kWhat), 1, owned);
  phi_i_ = floats(file, file.field("phi_i", kWhat), 1, owned);
  require(file, !theta_i_.empty() && !phi_i_.empty(), "no incident directions (theta_i or phi_i is empty)");
  check_sorted(file, theta_i_, "theta_i");
  check_sorted(file, phi_i_, "phi_i");
  const std::size_t nt = theta_i_.size(), np = phi_i_.size();

  const TensorField& ndf = file.field("ndf", kWhat);
  const TensorField& sigma = file.field("sigma", kWhat);
  const TensorField& vndf = file.field("vndf", kWhat);
  const TensorField& jacobian = file.field("jacobian", kWhat);
  const std::vector<float> ndf_v = floats(file, ndf, 2, owned), sigma_v = floats(file, sigma, 2, owned);
  const std::vector<float> vndf_v = floats(file, vndf, 4, owned);
  require(file, ndf.shape[0] >= 2 && ndf.shape[1] >= 2, "field 'ndf' is " + ndf.describe() + " (at least 2x2)");
  require(file, sigma.shape[0] >= 2 && sigma.shape[1] >= 2, "field 'sigma' is " + sigma.describe() + " (at least 2x2)");
  require(file, vndf.shape[0] == np && vndf.shape[1] == nt && vndf.shape[2] >= 2 && vndf.shape[3] >= 2,
          "field 'vndf' is " + vndf.describe() + ", expected [phi_i, theta_i, >=2, >=2] with " + std::to_string(np) +
              " phi_i and " + std::to_string(nt) + " theta_i");
  require(file, jacobian.dtype == TensorType::UInt8 && jacobian.count() == 1,
          "field 'jacobian' is " + jacobian.describe() + ", expected uint8 [1]");
  jacobian_ = static_cast<std::uint8_t>(jacobian.data[0]) != 0;
  for (float v : sigma_v) require(file, v > 0, "field 'sigma' has a value that is not positive");
  for (float v : vndf_v) require(file, v >= 0, "field 'vndf' has a negative value");
  for (float v : ndf_v) require(file, v >= 0, "field 'ndf' has a negative value");

  // Reflectance: RGB, or a spectrum reduced to RGB here. The largest field by far: converted
  // once, its bytes in the file freed (when owned), and moved into its table.
  const TensorField* rgb = file.find("rgb");
  const TensorField* spectra = file.find("spectra");
  if (!rgb && !spectra) file.field("rgb", kWhat);  // throws, listing the fields present
  const TensorField& refl = rgb ? *rgb : *spectra;
  std::vector<float> rgb_v = floats(file, refl, 5, owned);
  std::vector<float> wavelengths;
  if (!rgb) {
    wavelengths = floats(file, file.field("wavelengths", kWhat), 1, owned);
    check_sorted(file, wavelengths, "wavelengths");
    require(file, !wavelengths.empty(), "field 'wavelengths' is empty");
    wavelength_count_ = wavelengths.size();
  }
  const std::size_t channels = rgb ? 3 : wavelengths.size();
  require(file, refl.shape[0] == np && refl.shape[1] == nt && refl.shape[2] == channels && refl.shape[3] >= 2 &&
                    refl.shape[4] >= 2,
          "field '" + refl.name + "' is " + refl.describe() + ", expected [phi_i, theta_i, " + std::to_string(channels) +
              ", >=2, >=2]");
  const std::size_t ry = refl.shape[3], rx = refl.shape[4];
  if (!rgb) rgb_v = spectra_to_rgb(rgb_v, wavelengths, np * nt, rx * ry);

  isotropic_ = np <= 2;
  if (!isotropic_) {
    const double span = static_cast<double>(phi_i_.back()) - static_cast<double>(phi_i_.front());
    require(file, span > 0, "field 'phi_i' spans no angle");
    reduction_ = static_cast<int>(std::lrint(2 * kPi / span));
  }

  ndf_ = RglWarp2D(ndf_v, ndf.shape[1], ndf.shape[0], 1, false);
  sigma_ = RglWarp2D(sigma_v, sigma.shape[1], sigma.shape[0], 1, false);
  vndf_ = RglWarp2D(vndf_v, vndf.shape[3], vndf.shape[2], np * nt, true);
  for (std::size_t s = 0; s < np * nt; ++s)
    require(file, vndf_.slice_integral(s) > 0,
            "field 'vndf' is zero everywhere for incident direction " + std::to_string(s));
  negative_samples_ = static_cast<std::size_t>(std::count_if(rgb_v.begin(), rgb_v.end(), [](float v) { return v < 0; }));
  rgb_ = RglWarp2D(std::move(rgb_v), rx, ry, np * nt * 3);

  // The luminance warp, for sampling only: used when it has the reflectance's shape and a
  // positive integral everywhere (else sampling follows the VNDF alone, as Mitsuba without it).
  if (std::optional<RglWarp2D> lum = luminance_warp(file, owned, {np, nt, ry, rx})) {
    luminance_ = std::move(*lum);
    has_luminance_ = true;
  }
}

std::string RglBsdf::summary() const {
  std::string s = isotropic_ ? "isotropic" : "anisotropic";
  s += spectral() ? ", spectral (" + std::to_string(wavelength_count_) + " wavelengths, reduced to RGB)" : ", RGB";
  s += ", " + std::to_string(theta_i_.size()) + " x " + std::to_string(phi_i_.size()) +
       " incident directions, VNDF " + std::to_string(vndf_.nx()) + "x" + std::to_string(vndf_.ny()) +
       ", reflectance " + std::to_string(rgb_.nx()) + "x" + std::to_string(rgb_.ny());
  if (!jacobian_) s += ", no Jacobian";
  return s;
}

namespace {

/// A pair of directions as the tensors see it: folded by the file's symmetry (reduction 2 or 4,
/// as Mitsuba), wi's elevation and azimuth, and the half vector m with its unit coordinates (its
/// azimuth relative to wi's for isotropic files).
struct HalfVectorFrame {
  Vec3 wi, wo, m;
  double theta_i = 0, phi_i = 0;
  double u_m[2] = {0, 0};
};

/// The reciprocal value closest, in least squares, to both orders of a measured pair: forward is
/// f cos(theta_o) for (wi, wo), backward f cos(theta_i) for (wo, wi) (docs/RGL.md).
Rgb reciprocal_value(const Rgb& forward, const Rgb& backward, double ci, double co) {
  return (co * forward + ci * backward) / (ci * ci + co * co);
}

HalfVectorFrame half_vector_frame(const Vec3& wi_in, const Vec3& wo_in, int reduction, bool isotropic) {
  HalfVectorFrame f;
  f.wi = wi_in.normalized();
  f.wo = wo_in.normalized();
  if (reduction >= 2) {
    const double sy = f.wi.y(), sx = reduction == 4 ? f.wi.x() : sy;
    f.wi.x() = mulsign_neg(f.wi.x(), sx);
    f.wi.y() = mulsign_neg(f.wi.y(), sy);
    f.wo.x() = mulsign_neg(f.wo.x(), sx);
    f.wo.y() = mulsign_neg(f.wo.y(), sy);
  }
  f.m = (f.wi + f.wo).normalized();
  f.theta_i = elevation(f.wi);
  f.phi_i = std::atan2(f.wi.y(), f.wi.x());
  const double phi_m = std::atan2(f.m.y(), f.m.x());
  f.u_m[0] = theta_to_unit(elevation(f.m));
  f.u_m[1] = phi_to_unit(isotropic ? phi_m - f.phi_i : phi_m);
  f.u_m[1] -= std::floor(f.u_m[1]);
  return f;
}

}  // namespace

RglBsdf::ReflectanceLookup RglBsdf::reflectance_lookup(const Vec3& wi_in, const Vec3& wo_in) const {
  ReflectanceLookup r;
  if (!(wi_in.z() > 0.0) || !(wo_in.z() > 0.0) || !wi_in.allFinite() || !wo_in.allFinite()) return r;
  const HalfVectorFrame f = half_vector_frame(wi_in, wo_in, reduction_, isotropic_);
  const double(&u_m)[2] = f.u_m;
  const double u_wi[2] = {theta_to_unit(f.theta_i), phi_to_unit(f.phi_i)};
  r.valid = true;
  r.blend = blend_params(phi_i_, f.phi_i, theta_i_, f.theta_i);
  r.at = vndf_.invert(u_m[0], u_m[1], r.blend);
  r.scale = 1.0;
  if (jacobian_) {
    const ParamBlend none;
    const double s = sigma_.eval(u_wi[0], u_wi[1], none);
    r.scale = s > 0 ? ndf_.eval(u_m[0], u_m[1], none) / (4.0 * s) : 0.0;
  }
  return r;
}

Rgb RglBsdf::eval_cosine(const Vec3& wi, const Vec3& wo) const {
  const ReflectanceLookup r = reflectance_lookup(wi, wo);
  if (!r.valid) return Rgb::Zero();
  Rgb value;
  for (int c = 0; c < 3; ++c) {
    ParamBlend channel = r.blend;
    for (int b = 0; b < r.blend.count; ++b) channel.slice[static_cast<std::size_t>(b)] = 3 * r.blend.slice[static_cast<std::size_t>(b)] + static_cast<std::size_t>(c);
    value[c] = std::max(rgb_.eval(r.at[0], r.at[1], channel), 0.0);  // clipped, as RGL's loader
  }
  return value * r.scale;
}

namespace {

/// Mitsuba's measured-BSDF Jacobian from the half vector's unit coordinates to solid angle of wo:
/// dm = 2 pi^2 u sin(theta_m) du dv, dwo = 4 (wi.m) dm.
double rgl_sampling_jacobian(double u_theta, double sin_theta_m, double wi_dot_m) {
  return std::max(2.0 * kPi * kPi * u_theta * sin_theta_m, 1e-6) * 4.0 * wi_dot_m;
}

}  // namespace

RglBsdf::Sample RglBsdf::sample(const Vec3& wi_in, double u1, double u2) const {
  Sample out;
  if (!(wi_in.z() > 0.0) || !wi_in.allFinite()) return out;
  Vec3 wi = wi_in.normalized();
  double sx = 0, sy = 0;
  if (reduction_ >= 2) {
    sy = wi.y();
    sx = reduction_ == 4 ? wi.x() : sy;
    wi.x() = mulsign_neg(wi.x(), sx);
    wi.y() = mulsign_neg(wi.y(), sy);
  }
  const double theta_i = elevation(wi), phi_i = std::atan2(wi.y(), wi.x());
  const ParamBlend blend = blend_params(phi_i_, phi_i, theta_i_, theta_i);
  std::array<double, 2> s{u1, u2};
  double lum_pdf = 1.0;
  if (has_luminance_) {
    s = luminance_.sample(u1, u2, blend);
    lum_pdf = luminance_.eval(s[0], s[1], blend);
  }
  const auto u_m = vndf_.sample(s[0], s[1], blend);
  const double vndf_pdf = vndf_.eval(u_m[0], u_m[1], blend);
  const double theta_m = 0.5 * kPi * u_m[0] * u_m[0];
  double phi_m = 2.0 * kPi * u_m[1] - kPi;
  if (isotropic_) phi_m += phi_i;
  const double st = std::sin(theta_m);
  const Vec3 m(st * std::cos(phi_m), st * std::sin(phi_m), std::cos(theta_m));
  const double c = wi.dot(m);
  Vec3 wo = 2.0 * c * m - wi;
  if (reduction_ >= 2) {
    wo.x() = mulsign_neg(wo.x(), sx);
    wo.y() = mulsign_neg(wo.y(), sy);
  }
  if (!(wo.z() > 0.0) || !(c > 0.0)) return out;
  out.wo = wo;
  out.pdf = vndf_pdf * lum_pdf / rgl_sampling_jacobian(u_m[0], st, c);
  return out;
}

double RglBsdf::pdf(const Vec3& wi_in, const Vec3& wo_in) const {
  if (!(wi_in.z() > 0.0) || !(wo_in.z() > 0.0) || !wi_in.allFinite() || !wo_in.allFinite()) return 0.0;
  const HalfVectorFrame f = half_vector_frame(wi_in, wo_in, reduction_, isotropic_);
  const double(&u_m)[2] = f.u_m;
  const ParamBlend blend = blend_params(phi_i_, f.phi_i, theta_i_, f.theta_i);
  const double vndf_pdf = vndf_.eval(u_m[0], u_m[1], blend);
  double lum_pdf = 1.0;
  if (has_luminance_) {
    const auto s = vndf_.invert(u_m[0], u_m[1], blend);
    lum_pdf = luminance_.eval(s[0], s[1], blend);
  }
  return vndf_pdf * lum_pdf / rgl_sampling_jacobian(u_m[0], std::sin(elevation(f.m)), f.wi.dot(f.m));
}

Rgb RglBsdf::eval(const Vec3& wi, const Vec3& wo) const {
  if (!(wo.z() > 0.0) || !wo.allFinite()) return Rgb::Zero();
  return eval_cosine(wi, wo) / wo.normalized().z();
}

Rgb RglBsdf::eval_reciprocal(const Vec3& wi_in, const Vec3& wo_in) const {
  if (!(wi_in.z() > 0.0) || !(wo_in.z() > 0.0) || !wi_in.allFinite() || !wo_in.allFinite()) return Rgb::Zero();
  const Vec3 wi = wi_in.normalized(), wo = wo_in.normalized();
  return reciprocal_value(eval_cosine(wi, wo), eval_cosine(wo, wi), wi.z(), wo.z());
}

namespace {

/// Bins that end below this theta_h (0.2 rad, 11.5 deg: the first 32 of MERL's 90) hold the
/// average of the reciprocal value over their theta_h x theta_d extent, not its value at the
/// centre: there a specular peak can be narrower than a bin (chm_mint's is under 0.3 deg wide),
/// and a point sample added up to 1.6 % to the albedo. 4 x 4 sub-bins of equal width in the grid's
/// coordinates (square root in theta_h), weighted by the solid angle (d theta_h / du sin theta_h
/// sin theta_d; theta_d at the centre only in bins ending above 85 deg); values are clipped at 0
/// by the evaluation.
constexpr double kCellAveragedThetaH = 0.2;
constexpr int kThetaHSubBins = 4;
constexpr int kThetaDSubBins = 4;
constexpr double kCellAveragedMaxThetaDDeg = 85.0;

Rgb cell_average(const RglBsdf& bsdf, const MerlDims& dims, int i, int j, int k) {
  HalfDiffAngles a = bin_centre(dims, i, j, k);
  Rgb sum = Rgb::Zero();
  double weight_sum = 0.0;
  for (int s = 0; s < kThetaHSubBins; ++s) {
    const double u = (i + (s + 0.5) / kThetaHSubBins) / dims.theta_h;
    a.theta_h = u * u * (kPi / 2.0);
    // Near the horizon the reciprocal value grows faster than 1 / cos (the measured f cos does
    // not vanish there): averaged over theta_d, the sub-sample at 89.875 deg made the last bin
    // 1.7-1.9 times its centre value (all 18 RGL files checked). Bins ending above 85 deg take
    // theta_d at their centre (the averaging is for peaks narrow in theta_h, not theta_d).
    const bool grazing = static_cast<double>(j + 1) / dims.theta_d * 90.0 > kCellAveragedMaxThetaDDeg;
    const int theta_d_points = grazing ? 1 : kThetaDSubBins;
    for (int t = 0; t < theta_d_points; ++t) {
      a.theta_d = (j + (t + 0.5) / theta_d_points) / dims.theta_d * (kPi / 2.0);
      const DirectionPair d = from_half_diff(a);
      if (!(d.wi.z() > 0.0) || !(d.wo.z() > 0.0)) continue;
      const double w = u * std::sin(a.theta_h) * std::sin(a.theta_d);
      const Rgb value =
          reciprocal_value(bsdf.eval_cosine(d.wi, d.wo), bsdf.eval_cosine(d.wo, d.wi), d.wi.z(), d.wo.z());
      sum += w * value.max(0.0);
      weight_sum += w;
    }
  }
  return weight_sum > 0.0 ? Rgb(sum / weight_sum) : Rgb(Rgb::Zero());
}

}  // namespace

BrdfTable resample_to_merl(const RglBsdf& bsdf, RglResampling* report, const MerlDims& dims) {
  if (!bsdf.isotropic())
    throw file_error(bsdf.path(), "anisotropic material (" + std::to_string(bsdf.phi_i_count()) +
                                      " incident azimuths), not supported yet: the MERL grid holds isotropic "
                                      "BRDFs only");
  BrdfTable table(dims, ValueBuffer::Uninitialized{});
  struct Partial {
    std::size_t measured = 0, missing = 0, clamped = 0;
    double asym = 0, sym = 0;
    Rgb max = Rgb::Zero();
  };
  std::vector<Partial> partial(static_cast<std::size_t>(dims.theta_h));
  parallel_for_each(0, static_cast<std::size_t>(dims.theta_h), [&](std::size_t i) {
    Partial& p = partial[i];
    const double upper_u = static_cast<double>(i + 1) / dims.theta_h;
    const bool averaged = upper_u * upper_u * (kPi / 2.0) <= kCellAveragedThetaH;
    for (int j = 0; j < dims.theta_d; ++j) {
      for (int k = 0; k < dims.phi_d; ++k) {
        const std::size_t bin = dims.flat(static_cast<int>(i), j, k);
        const DirectionPair d = from_half_diff(bin_centre(dims, static_cast<int>(i), j, k));
        if (!(d.wi.z() > 0.0) || !(d.wo.z() > 0.0)) {
          for (int c = 0; c < 3; ++c) table.set_missing(c, bin);
          ++p.missing;
          continue;
        }
        // f cos(theta_o) in one order, f cos(theta_i) in the other.
        const Rgb forward = bsdf.eval_cosine(d.wi, d.wo), backward = bsdf.eval_cosine(d.wo, d.wi);
        const double ci = d.wi.z(), co = d.wo.z();
        p.asym += (ci * forward - co * backward).abs().sum();
        p.sym += 0.5 * (ci * forward.abs() + co * backward.abs()).sum();
        Rgb value = reciprocal_value(forward, backward, ci, co);
        for (int c = 0; c < 3; ++c) {
          if (value[c] < 0) {
            value[c] = 0;
            ++p.clamped;
          }
        }
        if (averaged) value = cell_average(bsdf, dims, static_cast<int>(i), j, k);
        for (int c = 0; c < 3; ++c) table.set_value(c, bin, value[c]);
        p.max = p.max.max(value);
        ++p.measured;
      }
    }
  });
  // What a MERL reader refuses must not come out of here: a crafted file (values near the float
  // range, or a sigma near 0 under the Jacobian) can give values of 1e38 or more.
  const auto stored = table.stored();
  for (std::size_t v = 0; v < stored.size(); ++v) {
    if (std::fabs(stored[v]) <= kMaxMerlMagnitude) continue;
    const std::size_t c = v / dims.bins(), bin = v % dims.bins();
    static const char* const channels[] = {"red", "green", "blue"};
    char text[64];
    std::snprintf(text, sizeof text, "%.6g (1/sr; %.6g in stored units)", stored[v] * BrdfTable::kChannelScale[c],
                  stored[v]);
    throw file_error(bsdf.path(), std::string("resampled onto the MERL grid, the material's value at bin ") +
                                      std::to_string(bin) + " (" + channels[c] + ") is " + text +
                                      ", beyond what MERL files hold (1e15 in stored units): not a plausible measurement");
  }
  if (report) {
    RglResampling r;
    r.bins = dims.bins();
    double asym = 0, sym = 0;
    for (const Partial& p : partial) {
      r.measured_bins += p.measured;
      r.missing_bins += p.missing;
      r.clamped_values += p.clamped;
      asym += p.asym;
      sym += p.sym;
      r.max_value = r.max_value.max(p.max);
    }
    r.reciprocity_error = sym > 0 ? asym / sym : 0.0;
    *report = r;
  }
  return table;
}

bool is_rgl_path(const fs::path& path) { return path.extension() == ".bsdf"; }

BrdfTable read_brdf(const fs::path& path) {
  if (is_rgl_path(path)) return resample_to_merl(RglBsdf::read(path));
  return read_merl(path);
}

}  // namespace matlas
