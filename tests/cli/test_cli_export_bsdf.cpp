// matlas export --format bsdf: table files, model points and materials written as RGL .bsdf files
// (atomically, read back by matlas' own reader), and refused with a message naming the file or
// flag when the input or the request is bad.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "brdf/analytic.h"
#include "brdf/catalog.h"
#include "brdf/tabulate.h"
#include "cli/in_process.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"
#include "formats/synth_database.h"
#include "formats/tensor_file.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

/// Every entry of a folder other than `keep` (temporary files left behind).
std::vector<std::string> bsdf_export_leftovers(const fs::path& dir, const std::vector<std::string>& keep) {
  std::vector<std::string> extra;
  for (const auto& e : fs::directory_iterator(dir))
    if (std::find(keep.begin(), keep.end(), e.path().filename().string()) == keep.end())
      extra.push_back(e.path().filename().string());
  return extra;
}

class CliExportBsdf : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-cli-export-bsdf");
    write_merl(table(), tabulate(Lambertian{Rgb(0.7, 0.5, 0.3)}));
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path table() { return dir_->path() / "lambert.binary"; }
  static inline test::TempDir* dir_ = nullptr;
};

TEST_F(CliExportBsdf, ATableFileBecomesABsdfFileByItsExtensionThatReproducesIt) {
  const test::TempDir out("matlas-cli-export-bsdf-out");
  const fs::path bsdf = out / "lambert.bsdf";
  const test::CliOutput r = test::call_matlas({"export", table().string(), "-o", bsdf.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "wrote " + bsdf.string() + " (RGL .bsdf, isotropic RGB");
  EXPECT_HAS(r.out, "relative RMS");
  EXPECT_HAS(r.out, "samples         fitted to the table in least squares");
  EXPECT_EQ(r.out.find("hint"), std::string::npos) << r.out;  // within 2 % and 1 %: no hint
  EXPECT_EQ(bsdf_export_leftovers(out.path(), {"lambert.bsdf"}), std::vector<std::string>{});
  // The file, read back by matlas' own reader, is the Lambertian (0.7, 0.5, 0.3) / pi.
  const RglBsdf b = RglBsdf::read(bsdf);
  EXPECT_TRUE(b.isotropic());
  EXPECT_EQ(b.description(), "matlas export of lambert.binary");
  const Vec3 wi(0.3, 0.1, 0.95), wo(-0.5, 0.2, 0.84);
  const Rgb f = b.eval(wi.normalized(), wo.normalized());
  EXPECT_NEAR(f[0], 0.7 / kPi, 0.01 * 0.7 / kPi);
  EXPECT_NEAR(f[2], 0.3 / kPi, 0.01 * 0.3 / kPi);
  // --format binary converts a table as it is (and is the default for other names).
  const test::CliOutput m = test::call_matlas({"export", table().string(), "-o", (out / "copy.binary").string()});
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(read_merl(out / "copy.binary").stored()[1000], read_merl(table()).stored()[1000]);
}

TEST_F(CliExportBsdf, AFileFarFromItsTableSaysThatMoreElevationsHelp) {
  // Four elevations cannot follow a glossy lobe: the check is above 2 % and the command says
  // which option brings the file closer; the file is written all the same.
  const test::TempDir out("matlas-cli-export-bsdf-coarse");
  RoughPlastic plastic;
  plastic.alpha = 0.1;
  write_merl(out / "glossy.binary", tabulate(plastic));
  const test::CliOutput r = test::call_matlas({"export", (out / "glossy.binary").string(), "-o",
                                               (out / "glossy.bsdf").string(), "--theta-i", "4", "--rgb-resolution", "16"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "hint            above 1 % in albedo or 2 % RMS: more incident elevations (--theta-i 48");
  EXPECT_TRUE(fs::exists(out / "glossy.bsdf"));
}

TEST_F(CliExportBsdf, ASpectralFileReproducesTheTableThroughItsSpectra) {
  const test::TempDir out("matlas-cli-export-bsdf-out");
  const fs::path bsdf = out / "spectral.bsdf";
  const test::CliOutput r = test::call_matlas({"export", table().string(), "--format", "bsdf-spectral", "--rgb-resolution",
                                               "24", "--wavelengths", "12", "-o", bsdf.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "isotropic spectral, 12 wavelengths 360-830 nm");
  EXPECT_HAS(r.out, "sigmoid spectra");
  const TensorFile file = TensorFile::read(bsdf);
  ASSERT_NE(file.find("spectra"), nullptr);
  EXPECT_EQ(file.find("rgb"), nullptr);
  EXPECT_EQ(file.field("spectra", "test").shape, (std::vector<std::uint64_t>{1, 32, 12, 24, 24}));
  EXPECT_EQ(file.field("wavelengths", "test").shape, std::vector<std::uint64_t>{12});
  // Read back through the spectra (the reader reduces them with the CIE functions): the
  // Lambertian (0.7, 0.5, 0.3) / pi.
  const RglBsdf b = RglBsdf::read(bsdf);
  EXPECT_TRUE(b.spectral());
  const Vec3 wi(0.3, 0.1, 0.95), wo(-0.5, 0.2, 0.84);
  const Rgb f = b.eval(wi.normalized(), wo.normalized());
  EXPECT_NEAR(f[0], 0.7 / kPi, 0.01 * 0.7 / kPi);
  EXPECT_NEAR(f[1], 0.5 / kPi, 0.01 * 0.5 / kPi);
  EXPECT_NEAR(f[2], 0.3 / kPi, 0.01 * 0.3 / kPi);
  const test::CliOutput w = test::call_matlas(
      {"export", table().string(), "--format", "bsdf-spectral", "--wavelengths", "2", "-o", (out / "w.bsdf").string()});
  EXPECT_EQ(w.code, 2);  // fewer than 3 wavelengths: a usage error
}

TEST_F(CliExportBsdf, ContradictoryOrUnknownFormatsAreRefusedBeforeWriting) {
  const test::TempDir out("matlas-cli-export-bsdf-out");
  const test::CliOutput a =
      test::call_matlas({"export", table().string(), "--format", "binary", "-o", (out / "x.bsdf").string()});
  EXPECT_EQ(a.code, 1);
  EXPECT_HAS(a.err, "a .bsdf name for --format binary");
  const test::CliOutput c =
      test::call_matlas({"export", table().string(), "--format", "exr", "-o", (out / "x.exr").string()});
  EXPECT_EQ(c.code, 1);
  EXPECT_HAS(c.err, "--format 'exr'");
  const test::CliOutput d = test::call_matlas(
      {"export", table().string(), "--material", "x", "--format", "bsdf", "-o", (out / "x.bsdf").string()});
  EXPECT_EQ(d.code, 1);
  EXPECT_HAS(d.err, table().string() + ": --at and --material pick a point of a model");
  const test::CliOutput e =
      test::call_matlas({"export", table().string(), "--theta-i", "1", "-o", (out / "x.bsdf").string()});
  EXPECT_EQ(e.code, 2);  // a flag's value out of range: a usage error
  EXPECT_EQ(bsdf_export_leftovers(out.path(), {}), std::vector<std::string>{});
}

TEST_F(CliExportBsdf, BadInputIsRefusedNamingTheFileAndNothingIsWritten) {
  const test::TempDir out("matlas-cli-export-bsdf-out");
  const fs::path broken = out / "broken.binary";
  std::ofstream(broken) << "not a MERL table";
  const test::CliOutput r = test::call_matlas({"export", broken.string(), "-o", (out / "x.bsdf").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_HAS(r.err, broken.string() + ":");
  EXPECT_FALSE(fs::exists(out / "x.bsdf"));
  // The output may not be the input (through a link too).
  fs::create_symlink(table(), out / "link.bsdf");
  const test::CliOutput s = test::call_matlas({"export", table().string(), "-o", (out / "link.bsdf").string()});
  EXPECT_EQ(s.code, 1);
  EXPECT_HAS(s.err, "link.bsdf");
  EXPECT_EQ(read_merl(table()).dims(), MerlDims{});  // untouched
  EXPECT_EQ(bsdf_export_leftovers(out.path(), {"broken.binary", "link.bsdf"}), std::vector<std::string>{});
}

TEST(CliExportBsdfModel, APointFarFromTheDataIsExportedWithAWarningNamingItsVariance) {
  const test::TempDir t("matlas-cli-export-bsdf-model");
  write_database(t / "db", random_catalog(4, 7), null_progress(), MerlDims{16, 16, 32});
  const fs::path m = t / "m.matlas";
  ASSERT_EQ(test::call_matlas({"build", (t / "db").string(), "-o", m.string(), "--quiet", "--dim", "2"}).code, 0);
  const test::CliOutput far =
      test::call_matlas({"export", m.string(), "--at", "40,40", "-o", (t / "far.bsdf").string(), "--no-check"});
  ASSERT_EQ(far.code, 0) << far.err;
  EXPECT_HAS(far.err, "warning: x = ");
  EXPECT_HAS(far.err, "is far from the data (predictive variance");
  EXPECT_NO_THROW(RglBsdf::read(t / "far.bsdf"));
  // A material's own point: no warning; the file names the material.
  const std::string name = fs::path(*fs::directory_iterator(t / "db")).stem().string();
  const test::CliOutput own = test::call_matlas(
      {"export", m.string(), "--material", name, "--format", "bsdf", "-o", (t / "own.x").string(), "--no-check"});
  ASSERT_EQ(own.code, 0) << own.err;
  EXPECT_TRUE(own.err.empty()) << own.err;
  EXPECT_HAS(RglBsdf::read(t / "own.x").description(), "material " + name);
}

}  // namespace
}  // namespace matlas
