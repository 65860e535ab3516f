// Export of MERL-grid tables as RGL .bsdf files: the fields and layout RGL's files have, the
// round trip table -> .bsdf -> matlas' own reader -> table on analytic BRDFs with known albedo,
// and the file's own importance sampling (unbiased, and better than cosine sampling). Small
// grids and files keep the suite fast under the sanitizers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "brdf/albedo.h"
#include "brdf/analytic.h"
#include "brdf/ndf_extraction.h"
#include "brdf/tabulate.h"
#include "formats/rgl_bsdf.h"
#include "formats/rgl_bsdf_writer.h"
#include "formats/rgl_export_check.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

/// A coarse MERL-like grid (the export works on any grid; 1/27 of the standard one's bins).
constexpr MerlDims kSmallDims{30, 30, 60};

RglExportOptions small_options() {
  RglExportOptions o;
  o.theta_i = 16;
  o.vndf_resolution = 64;
  o.rgb_resolution = 32;
  o.sigma_resolution = 64;
  o.ndf.nodes = 61;
  o.description = "test material";
  return o;
}

RglFidelityOptions quick_check() {
  RglFidelityOptions o;
  o.albedo_resolution = 90;  // a multiple of the grid's 30 theta_h bins
  o.samples = 4096;
  return o;
}

/// The file of `table`, written and read back through the tensor file's bytes.
RglBsdf round_trip(const BrdfTable& table, const RglExportOptions& options, RglExportReport* report = nullptr) {
  const std::vector<TensorField> fields = rgl_fields_from_table(table, options, report);
  const std::vector<std::byte> bytes = serialize_tensor_file(fields);
  return RglBsdf(TensorFile::parse(bytes, "exported.bsdf"));
}

TEST(RglBsdfWriter, WritesTheFieldsAndLayoutOfRglIsotropicFiles) {
  const BrdfTable table = tabulate(Lambertian{}, kSmallDims);
  RglExportReport report;
  const RglExportOptions o = small_options();
  const std::vector<TensorField> fields = rgl_fields_from_table(table, o, &report);
  const std::vector<std::string> names = {"version", "description", "phi_i", "theta_i", "sigma", "ndf",
                                          "vndf",    "luminance",   "rgb",   "jacobian", "valid"};
  ASSERT_EQ(fields.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) EXPECT_EQ(fields[k].name, names[k]);
  const TensorFile file = TensorFile::parse(serialize_tensor_file(fields), "x.bsdf");
  EXPECT_EQ(file.field("phi_i").describe(), "float32 [1]");
  EXPECT_EQ(file.field("theta_i").describe(), "float32 [16]");
  EXPECT_EQ(file.field("sigma").describe(), "float32 [2, 64]");
  EXPECT_EQ(file.field("ndf").describe(), "float32 [2, 61]");
  EXPECT_EQ(file.field("vndf").describe(), "float32 [1, 16, 64, 64]");
  EXPECT_EQ(file.field("luminance").describe(), "float32 [1, 16, 32, 32]");
  EXPECT_EQ(file.field("rgb").describe(), "float32 [1, 16, 3, 32, 32]");
  EXPECT_EQ(file.field("jacobian").describe(), "uint8 [1]");
  EXPECT_EQ(file.field("valid").describe(), "uint8 [2048]");  // 16 x 32 x 32 bits
  EXPECT_EQ(static_cast<int>(file.field("jacobian").data[0]), 1);
  // One valid bit per sample, set exactly where wo is above the horizon.
  std::size_t set = 0;
  for (std::byte b : file.field("valid").data)
    for (int k = 0; k < 8; ++k) set += (std::to_integer<unsigned>(b) >> k) & 1u;
  EXPECT_EQ(set, report.samples - report.below_horizon);
  EXPECT_GT(report.below_horizon, 0u);  // grazing incidence reflects some half vectors below
  const RglBsdf bsdf(file);
  EXPECT_TRUE(bsdf.isotropic());
  EXPECT_TRUE(bsdf.jacobian());
  EXPECT_TRUE(bsdf.has_luminance());
  EXPECT_EQ(bsdf.description(), "test material");
  EXPECT_EQ(bsdf.negative_samples(), 0u);
}

TEST(RglBsdfWriter, LambertianRoundTripKeepsItsKnownAlbedo) {
  const Lambertian lambert{Rgb(0.8, 0.4, 0.2)};
  const BrdfTable table = tabulate(lambert, kSmallDims);
  const RglBsdf file = round_trip(table, small_options());
  const RglFidelity f = check_rgl_fidelity(file, table, quick_check());
  EXPECT_LT(f.relative_rms, 0.01);
  for (std::size_t a = 0; a < f.angles_deg.size(); ++a) {
    // The analytic albedo is the Lambertian's own (0.8, 0.4, 0.2) at every angle.
    const Rgb rel = (f.file_albedo[a] - lambert.albedo).abs() / lambert.albedo;
    EXPECT_LT(rel.maxCoeff(), 0.01) << f.angles_deg[a] << " deg: " << f.file_albedo[a].transpose();
  }
  // Pointwise: the file at random pairs against the closed form (1 / sr).
  for (const auto& [ti, to, phi] : {std::array<double, 3>{10, 20, 1.0}, {45, 30, 2.5}, {70, 5, 0.3}}) {
    const Vec3 wi = direction_at_theta(ti * kPi / 180);
    const Vec3 wo(std::sin(to * kPi / 180) * std::cos(phi), std::sin(to * kPi / 180) * std::sin(phi), std::cos(to * kPi / 180));
    const Rgb v = file.eval(wi, wo);
    EXPECT_NEAR(v[0], 0.8 / kPi, 0.01 * 0.8 / kPi) << ti << " " << to;
  }
}

TEST(RglBsdfWriter, GlossyPlasticRoundTripWithinTolerance) {
  RoughPlastic plastic;
  plastic.diffuse = Rgb(0.5, 0.3, 0.1);
  plastic.alpha = 0.3;
  // The coarse test grid resolves a lobe of this width (a sharper one spans a few of its 30
  // theta_h bins, and then the table's own kinks dominate the comparison at its bin centres).
  const BrdfTable table = tabulate(plastic, kSmallDims);
  RglExportReport report;
  const RglBsdf file = round_trip(table, small_options(), &report);
  const RglFidelity f = check_rgl_fidelity(file, table, quick_check());
  std::printf("  rough plastic (alpha 0.3): relative RMS %.2f %%, albedo %.2f %%, NDF iterations %d (change %.1e)\n",
              100 * f.relative_rms, 100 * f.albedo_error, report.ndf.iterations, report.ndf.last_change);
  // Stated tolerance for the test's reduced file on its coarse grid (16 elevations, 32x32
  // samples; docs/EXPORT.md gives the default export's figures): 6 % pointwise, 1 % in albedo.
  EXPECT_LT(f.relative_rms, 0.06);
  EXPECT_LT(f.albedo_error, 0.01);
  // Against the analytic model itself (the table is a tabulation of it, 5 to 75 deg).
  for (std::size_t a = 1; a < f.angles_deg.size(); ++a) {
    const Vec3 view = direction_at_theta(f.angles_deg[a] * kPi / 180);
    const Rgb exact = half_vector_albedo(plastic, view, 600);
    EXPECT_LT(((f.file_albedo[a] - exact).abs() / exact).maxCoeff(), 0.03) << f.angles_deg[a] << " deg";
  }
}

TEST(RglBsdfWriter, OwnImportanceSamplingIsUnbiasedAndBeatsCosineSampling) {
  GgxConductor metal;
  metal.f0 = Rgb(0.9, 0.6, 0.3);
  metal.alpha = 0.08;
  const BrdfTable table = tabulate(metal, kSmallDims);
  const RglBsdf file = round_trip(table, small_options());
  const RglFidelity f = check_rgl_fidelity(file, table, quick_check());
  for (std::size_t a = 0; a < f.angles_deg.size(); ++a) {
    const Rgb& q = f.file_albedo[a];
    const double quadrature = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
    const double standard_error = std::sqrt(f.variance_own[a] / quick_check().samples);
    // Unbiased: the mean of the file's own estimator agrees with the quadrature of the same file.
    EXPECT_NEAR(f.sampled_albedo[a], quadrature, 4 * standard_error + 0.003 * quadrature) << f.angles_deg[a] << " deg";
    // A sharp lobe: sampling it beats cosine sampling by far.
    EXPECT_LT(f.variance_own[a], 0.1 * f.variance_cosine[a]) << f.angles_deg[a] << " deg";
  }
  // pdf() is the density of sample().
  const Vec3 view = direction_at_theta(0.6);
  for (double u : {0.1, 0.37, 0.8}) {
    const RglBsdf::Sample s = file.sample(view, u, 1 - u);
    ASSERT_GT(s.pdf, 0);
    EXPECT_NEAR(file.pdf(view, s.wo), s.pdf, 1e-3 * s.pdf);
  }
}

TEST(NdfExtraction, RecoversTheDistributionOfAMicrofacetModel) {
  // A GGX conductor of constant Fresnel: its back-scattering is D / (4 cos sigma) up to F, and the
  // power iterations recover D's shape (D(theta) / D(0)) from it.
  GgxConductor metal;
  metal.f0 = Rgb::Constant(1.0);
  metal.alpha = 0.3;
  const BrdfTable table = tabulate(metal, {90, 90, 8});
  NdfExtractionReport report;
  const MicrofacetNdf ndf = extract_ndf(table, {}, &report);
  EXPECT_LT(report.last_change, 1e-6);
  EXPECT_NEAR(ndf.normalisation(), 1.0, 1e-3);
  auto ggx = [&](double theta) {
    const double a2 = metal.alpha * metal.alpha, c = std::cos(theta);
    const double t = c * c * (a2 - 1) + 1;
    return a2 / (kPi * t * t);
  };
  for (double deg : {5.0, 15.0, 25.0, 40.0}) {
    const double theta = deg * kPi / 180;
    EXPECT_NEAR(ndf(theta) / ndf(0.0), ggx(theta) / ggx(0.0), 0.08 * ggx(theta) / ggx(0.0)) << deg << " deg";
  }
  // sigma of a normalised NDF: 1 at normal incidence, and above cos(theta) everywhere.
  EXPECT_NEAR(ndf.projected_area(0.0), 1.0, 1e-3);
  EXPECT_GT(ndf.projected_area(1.2), std::cos(1.2));
}

TEST(RglBsdfWriter, WritesAtomicallyAndTheReaderAcceptsTheFile) {
  const test::TempDir dir("matlas-bsdf-writer");
  const BrdfTable table = tabulate(Lambertian{}, kSmallDims);
  RglExportReport report;
  write_rgl_bsdf(dir / "lambert.bsdf", table, small_options(), &report);
  EXPECT_EQ(report.bytes, std::filesystem::file_size(dir / "lambert.bsdf"));
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename(), "lambert.bsdf") << "left behind: " << entry.path();
  EXPECT_NO_THROW(RglBsdf::read(dir / "lambert.bsdf"));
}

}  // namespace
}  // namespace matlas
