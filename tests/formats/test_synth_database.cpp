// Writing synthetic MERL databases (formats/synth_database.h).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "brdf/tabulate.h"
#include "core/error.h"
#include "formats/merl_file.h"
#include "formats/synth_database.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

const MerlDims kSmall{12, 12, 24};  // tests write small grids; `matlas synth` writes 90x90x180

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(SynthDatabase, SameSeedGivesIdenticalFilesAndOtherSeedsDiffer) {
  test::TempDir dir;
  const auto a = write_database(dir / "a", random_catalog(6, 42), null_progress(), kSmall);
  const auto b = write_database(dir / "b", random_catalog(6, 42), null_progress(), kSmall);
  const auto c = write_database(dir / "c", random_catalog(6, 43), null_progress(), kSmall);
  ASSERT_EQ(a.size(), 6u);
  ASSERT_EQ(b.size(), 6u);
  int differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].filename(), b[i].filename());
    EXPECT_EQ(bytes_of(a[i]), bytes_of(b[i])) << a[i];
    differing += a[i].filename() != c[i].filename() || bytes_of(a[i]) != bytes_of(c[i]);
  }
  EXPECT_GE(differing, 5);
}

TEST(SynthDatabase, DemoPresetFilesReadBackThroughReadMerl) {
  test::TempDir dir;
  const auto catalog = demo_catalog();
  const auto written = write_database(dir.path(), catalog, null_progress(), kSmall);
  ASSERT_EQ(written.size(), catalog.size());
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir.path())) files += entry.path().extension() == ".binary";
  EXPECT_EQ(files, catalog.size());  // unique names: nothing overwritten
  for (std::size_t i = 0; i < catalog.size(); ++i) {
    EXPECT_EQ(written[i], dir.path() / (catalog[i].name + ".binary"));
    const BrdfTable table = read_merl(written[i]);
    EXPECT_EQ(table.dims(), kSmall);
    EXPECT_EQ(table.missing_count(), 0u);
    const BrdfTable expected =
        tabulate([&](const Vec3& wi, const Vec3& wo) { return evaluate(catalog[i].brdf, wi, wo); }, kSmall);
    ASSERT_TRUE(std::equal(table.stored().begin(), table.stored().end(), expected.stored().begin()))
        << catalog[i].name;
  }
}

TEST(SynthDatabase, StandardGridFileIsAValidMerlFile) {
  test::TempDir dir;
  const std::vector<SynthMaterial> one = {{"ggx-gold-a0.20", GgxConductor{Rgb(1.0, 0.782, 0.344), 0.2}}};
  const auto written = write_database(dir.path(), one);
  EXPECT_EQ(fs::file_size(written[0]), 12u + 3u * 90u * 90u * 180u * 8u);
  const BrdfTable table = read_merl(written[0]);
  EXPECT_TRUE(table.dims().is_standard());
  // At normal incidence f = F0 D(0) G / 4 = F0 / (4 pi alpha^2), and the first bin is nearly there.
  const Rgb f = table.lookup(Vec3::UnitZ(), Vec3::UnitZ());
  EXPECT_NEAR(f[0], 1.0 / (4 * kPi * 0.04), 0.01 * f[0]);
}

TEST(SynthDatabase, ReportsProgressPerMaterial) {
  struct Counter final : ProgressSink {
    std::uint64_t last = 0, total = 0;
    void update(const std::string&, std::uint64_t done, std::uint64_t t) override { last = done, total = t; }
    void message(const std::string&) override {}
    void finish(const std::string&) override {}
  } counter;
  test::TempDir dir;
  write_database(dir.path(), random_catalog(3, 1), counter, kSmall);
  EXPECT_EQ(counter.total, 3u);
  EXPECT_EQ(counter.last, 3u);
}

TEST(SynthDatabase, RefusesBadFoldersNamesAndParameters) {
  test::TempDir dir;
  {
    std::ofstream(dir / "file") << "x";
  }
  EXPECT_THROW(write_database(dir / "file", random_catalog(1, 1), null_progress(), kSmall), Error);
  EXPECT_THROW(write_database(dir / "file" / "sub", random_catalog(1, 1), null_progress(), kSmall), Error);
  const std::vector<SynthMaterial> duplicate = {{"x", Lambertian{}}, {"x", Lambertian{}}};
  EXPECT_THROW(write_database(dir / "d", duplicate, null_progress(), kSmall), Error);
  const std::vector<SynthMaterial> escaping = {{"../x", Lambertian{}}};
  EXPECT_THROW(write_database(dir / "e", escaping, null_progress(), kSmall), Error);
  const std::vector<SynthMaterial> invalid = {{"ok", Lambertian{}}, {"bad", GgxConductor{Rgb::Ones(), 5.0}}};
  EXPECT_THROW(write_database(dir / "f", invalid, null_progress(), kSmall), Error);
  EXPECT_FALSE(fs::exists(dir / "f" / "ok.binary"));  // checked before anything is written
  try {
    write_database(dir / "file" / "sub", random_catalog(1, 1), null_progress(), kSmall);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sub"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace matlas
