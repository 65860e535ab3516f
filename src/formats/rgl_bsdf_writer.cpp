#include "formats/rgl_bsdf_writer.h"

#include <array>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/check.h"
#include "core/parallel.h"
#include "formats/rgl_bsdf.h"
#include "formats/rgl_sample_fit.h"
#include "formats/rgl_warp.h"
#include "formats/spectral_rgb.h"

namespace matlas {

namespace {

/// RGL's unit coordinate of an elevation, u = sqrt(2 theta / pi).
double writer_unit_of_theta(double theta) { return std::sqrt(std::max(theta, 0.0) * (2.0 / kPi)); }

/// The direction at unit coordinates (u of theta, v of phi), phi = 2 pi v - pi.
Vec3 writer_direction(double u, double v) {
  const double theta = 0.5 * kPi * u * u, phi = 2.0 * kPi * v - kPi;
  const double st = std::sin(theta);
  return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

constexpr double kWriterLuminance[3] = {0.2126, 0.7152, 0.0722};

std::vector<float> to_floats(const std::vector<double>& v) {
  std::vector<float> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = static_cast<float>(v[i]);
  return out;
}

}  // namespace

namespace {

/// The NDF and projected-area tables written to the file: D and sigma as float32 rows (two equal
/// rows: the azimuth axis of an isotropic material), and their warps for lookups.
struct NdfTables {
  std::vector<float> ndf, sigma;
  RglWarp2D ndf_warp, sigma_warp;

  NdfTables(const MicrofacetNdf& extracted, std::size_t sigma_resolution) {
    const std::size_t nd = extracted.nodes().size(), ns = sigma_resolution;
    std::vector<double> ndf_rows(2 * nd), sigma_rows(2 * ns);
    for (std::size_t x = 0; x < nd; ++x) ndf_rows[x] = ndf_rows[nd + x] = extracted.nodes()[x];
    for (std::size_t x = 0; x < ns; ++x) {
      const double u = static_cast<double>(x) / static_cast<double>(ns - 1);
      sigma_rows[x] = sigma_rows[ns + x] = std::max(extracted.projected_area(0.5 * kPi * u * u), 1e-12);
    }
    ndf = to_floats(ndf_rows);
    sigma = to_floats(sigma_rows);
    ndf_warp = RglWarp2D(ndf, nd, 2, 1, false);
    sigma_warp = RglWarp2D(sigma, ns, 2, 1, false);
  }
};

/// The incident elevations: denser towards grazing incidence, where the peak of a glossy table
/// grows fastest with theta_i (and where cos(theta_o) of the mirror direction goes to 0).
std::vector<float> incident_elevations(const RglExportOptions& o) {
  const auto nt = static_cast<std::size_t>(o.theta_i);
  std::vector<float> theta(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const double x = static_cast<double>(t) / static_cast<double>(nt - 1);
    const double g = o.grazing_refinement;
    const double spread = (1.0 - g) * x + g * std::sin(0.5 * kPi * x);
    theta[t] = static_cast<float>(spread * o.theta_max_deg * kPi / 180.0);
  }
  return theta;
}

/// What the fields are computed from: the table, its NDF tables and the incident elevations.
struct FieldSource {
  const BrdfTable& table;
  const RglExportOptions& o;
  const NdfTables& ndf;
  const std::vector<float>& theta;

  Vec3 incident(std::size_t t) const {
    const double th = theta[t];
    return Vec3(std::sin(th), 0.0, std::max(std::cos(th), 0.0));  // float(pi / 2) is a bit above pi / 2
  }
  double sigma_at(std::size_t t) const { return ndf.sigma_warp.eval(writer_unit_of_theta(theta[t]), 0.5, ParamBlend{}); }
  /// VNDF per incident elevation: D(m) max(0, wi.m) / sigma(wi), times the unit square's
  /// Jacobian. The density of the VNDF on the unit square (unnormalised: its integral is 1 up to
  /// the grid).
  double vndf_density(const Vec3& wi, double sigma, double u, double v) const {
    const Vec3 m = writer_direction(u, v);
    const double jacobian = 2.0 * kPi * kPi * u * std::sin(0.5 * kPi * u * u);
    return ndf.ndf_warp.eval(u, v, ParamBlend{}) * std::max(0.0, wi.dot(m)) * jacobian / sigma;
  }

  /// The warp written: the VNDF mixed with a density of theta_m alone, 1 / sqrt(u + u0) (u0 =
  /// one cell), which puts samples where the table varies faster than the extracted NDF predicts
  /// (near the specular peak, at grazing angles); the luminance field carries the ratio, so that
  /// the file's sampling still follows the reflected light (docs/EXPORT.md).
  std::vector<float> vndf_field() const {
    const std::size_t nt = theta.size();
    const auto nv = static_cast<std::size_t>(o.vndf_resolution);
    const double u0 = 1.0 / static_cast<double>(nv - 1);
    std::vector<float> vndf(nt * nv * nv);
    parallel_for_each(0, nt, [&](std::size_t t) {
      const Vec3 wi = incident(t);
      const double sigma = sigma_at(t);
      std::vector<double> a(nv * nv), b(nv * nv);
      double sa = 0, sb = 0;
      for (std::size_t y = 0; y < nv; ++y)
        for (std::size_t x = 0; x < nv; ++x) {
          const double u = static_cast<double>(x) / static_cast<double>(nv - 1);
          const double v = static_cast<double>(y) / static_cast<double>(nv - 1);
          a[y * nv + x] = vndf_density(wi, sigma, u, v);
          b[y * nv + x] = 1.0 / std::sqrt(u + u0);
          sa += a[y * nv + x];
          sb += b[y * nv + x];
        }
      for (std::size_t k = 0; k < nv * nv; ++k)
        vndf[t * nv * nv + k] = static_cast<float>((1.0 - o.resolution_mix) * a[k] / sa + o.resolution_mix * b[k] / sb);
    });
    return vndf;
  }

  /// Reflectance samples at the nodes of the unit square, through the VNDF's sample warp: rgb,
  /// the ratio of the VNDF to the warp's density there (what turns the samples' luminance into
  /// the integrand on the square), and whether each is above the horizon.
  void reflectance_fields(const RglWarp2D& vndf_w, std::vector<float>& rgb, std::vector<double>& ratio,
                          std::vector<std::uint8_t>& valid) const {
    const std::size_t nt = theta.size();
    const auto nr = static_cast<std::size_t>(o.rgb_resolution);
    const std::size_t grid = nr * nr;
    rgb.assign(nt * 3 * grid, 0.0f);
    ratio.assign(nt * grid, 0.0);
    valid.assign(nt * grid, 0);
    parallel_for_each(0, nt, [&](std::size_t t) {
      const Vec3 wi = incident(t);
      const double sigma = sigma_at(t);
      ParamBlend slice;
      slice.slice[0] = t;
      for (std::size_t y = 0; y < nr; ++y)
        for (std::size_t x = 0; x < nr; ++x) {
          const auto u_m = vndf_w.sample(static_cast<double>(x) / static_cast<double>(nr - 1),
                                         static_cast<double>(y) / static_cast<double>(nr - 1), slice);
          const Vec3 m = writer_direction(u_m[0], u_m[1]);
          const double c = wi.dot(m);
          const Vec3 wo = 2.0 * c * m - wi;
          Rgb value = Rgb::Zero();
          const std::size_t at = y * nr + x;
          if (c > 0 && wo.z() > 0) {
            const double d = ndf.ndf_warp.eval(u_m[0], u_m[1], ParamBlend{});
            value = table.lookup_smooth(wi, wo.normalized()).max(0.0) * (wo.z() * 4.0 * sigma / d);
            valid[t * grid + at] = 1;
          }
          for (std::size_t ch = 0; ch < 3; ++ch)
            rgb[(t * 3 + ch) * grid + at] = static_cast<float>(value[static_cast<Eigen::Index>(ch)]);
          const double warp = vndf_w.eval(u_m[0], u_m[1], slice);
          ratio[t * grid + at] = warp > 0 ? vndf_density(wi, sigma, u_m[0], u_m[1]) / warp : 0.0;
        }
    });
  }
};

/// The luminance field: the integrand of the albedo on the reflectance's square (the samples'
/// luminance times the VNDF over the warp's density), the density of the file's importance
/// sampling. A slice that is black everywhere is sampled uniformly, and a small floor (1e-4 of the
/// slice's mean) keeps every region reachable.
std::vector<float> luminance_field(const std::vector<float>& rgb, const std::vector<double>& ratio, std::size_t nt,
                                   std::size_t grid) {
  std::vector<float> lum(nt * grid, 0.0f);
  parallel_for_each(0, nt, [&](std::size_t t) {
    double mean = 0;
    for (std::size_t k = 0; k < grid; ++k) {
      double l = 0;
      for (std::size_t ch = 0; ch < 3; ++ch) l += kWriterLuminance[ch] * rgb[(t * 3 + ch) * grid + k];
      lum[t * grid + k] = static_cast<float>(std::max(l * ratio[t * grid + k], 0.0));
      mean += lum[t * grid + k];
    }
    mean /= static_cast<double>(grid);
    for (std::size_t k = 0; k < grid; ++k)
      lum[t * grid + k] = mean > 0 ? static_cast<float>(lum[t * grid + k] + 1e-4 * mean) : 1.0f;
  });
  return lum;
}

/// The spectral file's samples: each RGB sample raised to a sigmoid spectrum at the upsampler's
/// wavelengths, [Nt][W][grid]; within a slice each fit starts from the previous sample's.
std::vector<float> rgb_to_spectra(const std::vector<float>& rgb, std::size_t nt, std::size_t grid,
                                  const SpectralUpsampler& up, RglExportReport& r) {
  const std::size_t nw = up.wavelengths().size();
  std::vector<float> spectra(nt * nw * grid, 0.0f);
  std::vector<double> sum_sq(nt, 0.0), worst(nt, 0.0);
  parallel_for_each(0, nt, [&](std::size_t t) {
    SpectralUpsampler::Fit previous;
    std::vector<float> s(nw);
    for (std::size_t k = 0; k < grid; ++k) {
      const std::array<double, 3> value{rgb[(t * 3 + 0) * grid + k], rgb[(t * 3 + 1) * grid + k], rgb[(t * 3 + 2) * grid + k]};
      const SpectralUpsampler::Fit f = up.fit(value, &previous);
      if (f.scale > 0) previous = f;
      up.spectrum(f, s.data());
      for (std::size_t w = 0; w < nw; ++w) spectra[(t * nw + w) * grid + k] = s[w];
      sum_sq[t] += f.error * f.error;
      worst[t] = std::max(worst[t], f.error);
    }
  });
  double total = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    total += sum_sq[t];
    r.spectral_error_max = std::max(r.spectral_error_max, worst[t]);
  }
  r.spectral_error_rms = std::sqrt(total / static_cast<double>(nt * grid));
  return spectra;
}

}  // namespace

std::vector<TensorField> rgl_fields_from_table(const BrdfTable& table, const RglExportOptions& o,
                                               RglExportReport* report) {
  MATLAS_CHECK_GE(o.theta_i, 2);
  MATLAS_CHECK_GE(o.vndf_resolution, 2);
  MATLAS_CHECK_GE(o.rgb_resolution, 2);
  MATLAS_CHECK_GE(o.sigma_resolution, 2);
  MATLAS_CHECK(o.theta_max_deg > 0 && o.theta_max_deg <= 90, "theta_max_deg out of (0, 90]");
  MATLAS_CHECK(o.wavelengths == 0 || o.wavelengths >= 3, "a spectral file needs at least 3 wavelengths");
  RglExportReport r;
  const NdfTables ndf(extract_ndf(table, o.ndf, &r.ndf), static_cast<std::size_t>(o.sigma_resolution));
  const std::vector<float> theta_f = incident_elevations(o);
  const FieldSource source{table, o, ndf, theta_f};
  const std::size_t nt = theta_f.size(), nv = static_cast<std::size_t>(o.vndf_resolution);
  const std::vector<float> vndf_f = source.vndf_field();
  const RglWarp2D vndf_w(vndf_f, nv, nv, nt, true);
  for (std::size_t t = 0; t < nt; ++t) MATLAS_CHECK_GT(vndf_w.slice_integral(t), 0.0);
  std::vector<float> rgb_f;
  std::vector<double> ratio;
  std::vector<std::uint8_t> valid;
  source.reflectance_fields(vndf_w, rgb_f, ratio, valid);

  const auto nr = static_cast<std::size_t>(o.rgb_resolution);
  const std::string description = o.description.empty() ? std::string("matlas export") : o.description;
  const std::uint8_t version[2] = {1, 0}, jacobian[1] = {1};
  const float phi_i[1] = {0.0f};
  const std::size_t nd = ndf.ndf.size() / 2, ns = ndf.sigma.size() / 2;
  std::vector<TensorField> fields;
  fields.push_back(uint8_field("version", {2}, version));
  fields.push_back(uint8_field("description", {description.size()},
                               {reinterpret_cast<const std::uint8_t*>(description.data()), description.size()}));
  fields.push_back(float32_field("phi_i", {1}, phi_i));
  fields.push_back(float32_field("theta_i", {nt}, theta_f));
  fields.push_back(float32_field("sigma", {2, ns}, ndf.sigma));
  fields.push_back(float32_field("ndf", {2, nd}, ndf.ndf));
  fields.push_back(float32_field("vndf", {1, nt, nv, nv}, vndf_f));

  if (o.fit.iterations > 0) {
    // The file as a reader sees it (without the sampling fields), for the fit's lookups.
    TensorFile probe;
    for (const TensorField& f : fields) probe.add(f);
    probe.add(float32_field("rgb", {1, nt, 3, nr, nr}, rgb_f));
    probe.add(uint8_field("jacobian", {1}, jacobian));
    const RglBsdf file(std::move(probe));
    r.fit = fit_rgl_samples(file, table, rgb_f, o.fit);
  }
  const std::vector<float> lum_f = luminance_field(rgb_f, ratio, nt, nr * nr);

  r.samples = nt * nr * nr;
  for (std::size_t k = 0; k < valid.size(); ++k) r.below_horizon += valid[k] ? 0 : 1;
  for (float v : rgb_f) {
    MATLAS_CHECK(std::isfinite(v), "a reflectance sample is not finite");
    r.largest_value = std::max(r.largest_value, static_cast<double>(v));
  }
  std::vector<std::uint8_t> valid_bits((valid.size() + 7) / 8, 0);
  for (std::size_t k = 0; k < valid.size(); ++k)
    if (valid[k]) valid_bits[k / 8] = static_cast<std::uint8_t>(valid_bits[k / 8] | (0x80u >> (k % 8)));

  fields.push_back(float32_field("luminance", {1, nt, nr, nr}, lum_f));
  if (o.wavelengths == 0) {
    fields.push_back(float32_field("rgb", {1, nt, 3, nr, nr}, rgb_f));
  } else {
    const auto nw = static_cast<std::size_t>(o.wavelengths);
    std::vector<float> wavelengths(nw);
    for (std::size_t w = 0; w < nw; ++w)
      wavelengths[w] = static_cast<float>(360.0 + 470.0 * static_cast<double>(w) / static_cast<double>(nw - 1));
    const SpectralUpsampler up(wavelengths);
    fields.push_back(float32_field("wavelengths", {nw}, wavelengths));
    fields.push_back(float32_field("spectra", {1, nt, nw, nr, nr}, rgb_to_spectra(rgb_f, nt, nr * nr, up, r)));
  }
  fields.push_back(uint8_field("jacobian", {1}, jacobian));
  fields.push_back(uint8_field("valid", {valid_bits.size()}, valid_bits));
  if (report) *report = r;
  return fields;
}

void write_rgl_bsdf(const std::filesystem::path& path, const BrdfTable& table, const RglExportOptions& options,
                    RglExportReport* report) {
  RglExportReport r;
  const std::vector<TensorField> fields = rgl_fields_from_table(table, options, &r);
  write_tensor_file(path, fields);
  r.bytes = static_cast<std::size_t>(std::filesystem::file_size(path));
  if (report) *report = r;
}

}  // namespace matlas
