// matlas import: RGL .bsdf files become MERL .binary files that matlas' own reader accepts, or
// nothing is written.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli/in_process.h"
#include "formats/merl_file.h"
#include "formats/tensor_file.h"
#include "support/synthetic_rgl.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

TEST(CliImport, WritesOnlyTablesTheMerlReaderAccepts) {
  const test::TempDir dir("matlas-cli-import");
  test::SyntheticRgl plain;
  write_tensor_file(dir / "plain.bsdf", plain.fields());
  test::SyntheticRgl bright = plain;
  bright.scale = 1e30;  // finite float32 values, resampled to about 1e33 in stored units
  write_tensor_file(dir / "bright.bsdf", bright.fields());

  const test::CliOutput ok =
      test::call_matlas({"import", (dir / "plain.bsdf").string(), "-o", (dir / "out").string(), "--no-check"});
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(read_merl(dir / "out" / "plain.binary").dims(), MerlDims{});

  // Used to write bright.binary, which `matlas build` and every reader then refused ("absurd value").
  const test::CliOutput bad =
      test::call_matlas({"import", (dir / "bright.bsdf").string(), "-o", (dir / "out").string(), "--no-check"});
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find((dir / "bright.bsdf").string() + ": resampled onto the MERL grid, the material's value at bin "),
            std::string::npos)
      << bad.err;
  EXPECT_NE(bad.err.find("beyond what MERL files hold"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "bright.binary"));
}

TEST(CliImport, RefusesAnOutputThatIsItsInputThroughALink) {
  const test::TempDir dir("matlas-cli-import-link");
  test::SyntheticRgl plain;
  std::filesystem::create_directories(dir / "out");
  write_tensor_file(dir / "out" / "a.bin", plain.fields());
  // a.bsdf (the input) is a hard link to out/a.binary, which import would write.
  std::filesystem::create_hard_link(dir / "out" / "a.bin", dir / "a.bsdf");
  std::filesystem::rename(dir / "out" / "a.bin", dir / "out" / "a.binary");
  const auto before = std::filesystem::file_size(dir / "a.bsdf");
  const test::CliOutput r =
      test::call_matlas({"import", (dir / "a.bsdf").string(), "-o", (dir / "out").string(), "--no-check"});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("a.binary"), std::string::npos) << r.err;
  EXPECT_EQ(std::filesystem::file_size(dir / "a.bsdf"), before);  // the input is intact
}

}  // namespace
}  // namespace matlas
