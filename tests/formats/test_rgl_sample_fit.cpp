// The least-squares fit of an RGL file's reflectance samples to its table
// (formats/rgl_sample_fit.h): the reader is the linear function of the samples the fit assumes,
// the fit's own figures agree with the reader's evaluation, and the fitted file is closer to the
// table at the bin centres and no farther between them than the file of point samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <random>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "formats/rgl_bsdf.h"
#include "formats/rgl_bsdf_writer.h"
#include "formats/rgl_export_check.h"
#include "formats/rgl_sample_fit.h"

namespace matlas {
namespace {

constexpr MerlDims kFitDims{30, 30, 60};

/// A small file (12 elevations, 24 x 24 samples) for the small grid.
RglExportOptions fit_options(int iterations) {
  RglExportOptions o;
  o.theta_i = 12, o.vndf_resolution = 48, o.rgb_resolution = 24;
  o.sigma_resolution = 64, o.ndf.nodes = 61;
  o.fit.iterations = iterations;
  return o;
}

RglFidelityOptions fit_check() {
  RglFidelityOptions o;
  o.albedo_resolution = 90;
  o.samples = 256;
  return o;
}

/// A glossy plastic whose highlight spans a few of the small grid's bins: the file's linear
/// interpolation between elevations and sample points is visibly off between its samples.
BrdfTable glossy_table() {
  RoughPlastic plastic;
  plastic.diffuse = Rgb(0.4, 0.25, 0.1);
  plastic.alpha = 0.15;
  return tabulate(plastic, kFitDims);
}

RglBsdf read_fields(const std::vector<TensorField>& fields) {
  return RglBsdf(TensorFile::parse(serialize_tensor_file(fields), "fitted.bsdf"));
}

std::vector<float> field_floats(const std::vector<TensorField>& fields, const std::string& name) {
  for (const TensorField& f : fields)
    if (f.name == name) {
      std::vector<float> v(f.data.size() / sizeof(float));
      std::memcpy(v.data(), f.data.data(), f.data.size());
      return v;
    }
  ADD_FAILURE() << "no field " << name;
  return {};
}

TEST(RglSampleFit, TheReaderIsTheLinearFunctionOfTheSamplesTheFitAssumes) {
  const std::vector<TensorField> fields = rgl_fields_from_table(glossy_table(), fit_options(0));
  const RglBsdf file = read_fields(fields);
  const std::vector<float> rgb = field_floats(fields, "rgb");
  const std::size_t nx = file.reflectance_nx(), grid = nx * file.reflectance_ny();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int checked = 0;
  for (int n = 0; n < 500; ++n) {
    const double ti = std::acos(uniform(rng)), to = std::acos(uniform(rng)), phi = 2 * kPi * uniform(rng);
    const Vec3 wi(std::sin(ti), 0, std::cos(ti));
    const Vec3 wo(std::sin(to) * std::cos(phi), std::sin(to) * std::sin(phi), std::cos(to));
    const RglBsdf::ReflectanceLookup l = file.reflectance_lookup(wi, wo);
    ASSERT_TRUE(l.valid);
    const RglWarp2D::Cell c = file.reflectance_cell(l);
    const std::size_t corner = c.py * nx + c.px;
    const double w[4] = {(1 - c.s) * (1 - c.t), c.s * (1 - c.t), (1 - c.s) * c.t, c.s * c.t};
    const std::size_t offset[4] = {0, 1, nx, nx + 1};
    for (std::size_t k = 0; k < 4; ++k) EXPECT_DOUBLE_EQ(c.weights()[k], w[k]);  // what the fit uses
    const Rgb expected = file.eval_cosine(wi, wo);
    for (int ch = 0; ch < 3; ++ch) {
      double sum = 0;
      for (int b = 0; b < l.blend.count; ++b)
        for (int k = 0; k < 4; ++k)
          sum += l.blend.weight[static_cast<std::size_t>(b)] * w[k] *
                 rgb[(l.blend.slice[static_cast<std::size_t>(b)] * 3 + static_cast<std::size_t>(ch)) * grid + corner + offset[k]];
      EXPECT_NEAR(l.scale * std::max(sum, 0.0), expected[ch], 1e-9 * (1 + std::abs(expected[ch]))) << n << " " << ch;
    }
    checked += expected.maxCoeff() > 0;
  }
  EXPECT_GT(checked, 400);
  // Below the horizon nothing is looked up.
  EXPECT_FALSE(file.reflectance_lookup(Vec3(0, 0, 1), Vec3(1, 0, -0.1)).valid);
}

TEST(RglSampleFit, ItsFiguresAreTheReadersAtTheBinCentres) {
  // Fitted at the bin centres alone, the fit's relative RMS before and after is the one the
  // export's check computes from the file read back (independently: through eval()).
  const BrdfTable table = glossy_table();
  RglExportOptions o = fit_options(30);
  o.fit.corners = false;
  RglExportReport report;
  const RglBsdf fitted = read_fields(rgl_fields_from_table(table, o, &report));
  const RglBsdf plain = read_fields(rgl_fields_from_table(table, fit_options(0)));
  const RglFidelity f = check_rgl_fidelity(fitted, table, fit_check());
  const RglFidelity p = check_rgl_fidelity(plain, table, fit_check());
  EXPECT_EQ(report.fit.iterations, report.fit.clipped > 0 ? 45 : 30);  // again, half as many, after a clip
  EXPECT_GT(report.fit.observations, kFitDims.bins() / 3);
  EXPECT_NEAR(report.fit.relative_rms_before, p.relative_rms, 1e-4 * p.relative_rms);
  EXPECT_NEAR(report.fit.relative_rms_after, f.relative_rms, 1e-3 * f.relative_rms);
  EXPECT_LT(f.relative_rms, 0.7 * p.relative_rms);
}

TEST(RglSampleFit, TheFittedFileIsCloserAtTheCentresAndNotFartherBetweenThem) {
  const BrdfTable table = glossy_table();
  RglExportReport report;
  const std::vector<TensorField> fitted_fields = rgl_fields_from_table(table, fit_options(RglSampleFitOptions{}.iterations), &report);
  const std::vector<TensorField> plain_fields = rgl_fields_from_table(table, fit_options(0));
  const RglBsdf fitted = read_fields(fitted_fields), plain = read_fields(plain_fields);
  const RglFidelity f = check_rgl_fidelity(fitted, table, fit_check());
  const RglFidelity p = check_rgl_fidelity(plain, table, fit_check());
  std::printf("  glossy plastic: relative RMS %.2f %% -> %.2f %% at the centres, %.2f %% -> %.2f %% between them\n",
              100 * p.relative_rms, 100 * f.relative_rms, 100 * p.relative_rms_between, 100 * f.relative_rms_between);
  EXPECT_LT(f.relative_rms, 0.8 * p.relative_rms);
  EXPECT_LT(f.relative_rms_between, p.relative_rms_between);
  std::printf("  albedo difference %.2f %% -> %.2f %% (0-75 deg)\n", 100 * p.albedo_error, 100 * f.albedo_error);
  EXPECT_LT(f.albedo_error, p.albedo_error);
  EXPECT_LT(f.albedo_error, 0.02);
  // The slice at normal incidence keeps the point samples (a renderer sees it alone at 0 deg), the
  // others moved, none below 0.
  const std::vector<float> a = field_floats(fitted_fields, "rgb"), b = field_floats(plain_fields, "rgb");
  const std::size_t slice = 3 * fitted.reflectance_nx() * fitted.reflectance_ny();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(std::equal(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(slice), b.begin()));
  EXPECT_FALSE(std::equal(a.begin() + static_cast<std::ptrdiff_t>(slice), a.end(), b.begin() + static_cast<std::ptrdiff_t>(slice)));
  EXPECT_GE(*std::min_element(a.begin(), a.end()), 0.0f);
  EXPECT_NEAR(f.file_albedo[0][0], p.file_albedo[0][0], 1e-12);
  // The fit's own figures (at the centres and corners) improved.
  EXPECT_GT(report.fit.observations, 0u);
  EXPECT_LT(report.fit.relative_rms_after, report.fit.relative_rms_before);
}

TEST(RglSampleFit, AlbedoRowsBringTheFilesAlbedoToTheTables) {
  // The rows for the directional albedo at every elevation and midway between: the file's albedo
  // (as a renderer integrates it, the check's six angles) closer to the table's than with the
  // points alone, at about the same RMS.
  const BrdfTable table = glossy_table();
  RglExportOptions without = fit_options(RglSampleFitOptions{}.iterations);
  without.fit.albedo_weight = 0;
  const RglExportOptions with = fit_options(RglSampleFitOptions{}.iterations);
  ASSERT_GT(with.fit.albedo_weight, 0);
  const RglFidelity a = check_rgl_fidelity(read_fields(rgl_fields_from_table(table, without)), table, fit_check());
  const RglFidelity b = check_rgl_fidelity(read_fields(rgl_fields_from_table(table, with)), table, fit_check());
  std::printf("  glossy plastic: albedo %.2f %% -> %.2f %% with the albedo rows, RMS %.2f %% -> %.2f %%\n",
              100 * a.albedo_error, 100 * b.albedo_error, 100 * a.relative_rms, 100 * b.relative_rms);
  EXPECT_LT(b.albedo_error, 0.8 * a.albedo_error);
  EXPECT_LT(b.relative_rms, 1.1 * a.relative_rms);
}

}  // namespace
}  // namespace matlas
