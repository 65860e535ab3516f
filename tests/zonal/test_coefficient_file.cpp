// The coefficient file: round trip in f32 and f16 with the storage error measured, errors
// naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "support/temp_dir.h"
#include "zonal/coefficient_file.h"
#include "zonal/shade.h"

namespace matlas::zonal {
namespace {

CoefficientSet small_set() {
  CoefficientSet set;
  set.settings.bands = 8;
  set.settings.theta_o_count = 8;
  const ZonalProjector projector(set.settings);
  set.names = {"plastic", "gold"};
  set.materials.push_back(projector.project(tabulate(RoughPlastic{Rgb(0.5, 0.2, 0.1), 0.1, 1.5, 1.0})));
  set.materials.push_back(projector.project(tabulate(GgxConductor{Rgb(1.0, 0.8, 0.4), 0.15})));
  set.mean = combine({&set.materials[0], &set.materials[1]}, {0.5, 0.5});
  return set;
}

double largest(const CoefficientSet& s) {
  double m = 0;
  for (const auto& c : s.materials)
    for (double v : c.values) m = std::max(m, std::abs(v));
  return m;
}

TEST(CoefficientFile, RoundTripsInF32AndF16WithTheErrorMeasured) {
  test::TempDir dir;
  const CoefficientSet set = small_set();
  const double scale = largest(set);
  for (DType storage : {DType::F32, DType::F16}) {
    const auto path = dir / "c.safetensors";
    const double reported = write_coefficients(path, set, storage);
    const CoefficientSet back = read_coefficients(path);
    EXPECT_EQ(back.names, set.names);
    EXPECT_EQ(back.settings.bands, 8);
    ASSERT_EQ(back.materials.size(), 2u);
    ASSERT_TRUE(back.mean.has_value());
    double error = 0;
    for (std::size_t i = 0; i < 2; ++i)
      for (std::size_t v = 0; v < set.materials[i].values.size(); ++v)
        error = std::max(error, std::abs(back.materials[i].values[v] - set.materials[i].values[v]));
    for (std::size_t v = 0; v < set.mean->values.size(); ++v)
      error = std::max(error, std::abs(back.mean->values[v] - set.mean->values[v]));
    EXPECT_NEAR(error / scale, reported, 1e-3 * reported + 1e-12);
    EXPECT_LT(reported, storage == DType::F16 ? 1e-3 : 1e-7);
    EXPECT_GT(reported, storage == DType::F16 ? 1e-5 : 0.0);
  }
}

TEST(CoefficientFile, F16ShadingDiffersByLessThanATenthOfAPercent) {
  test::TempDir dir;
  const CoefficientSet set = small_set();
  write_coefficients(dir / "h.safetensors", set, DType::F16);
  const CoefficientSet half = read_coefficients(dir / "h.safetensors");
  PrefilterSettings fs;
  fs.bands = 8;
  const PrefilteredEnvironment env(render::Environment::constant(Rgb(1.0, 0.9, 0.8)), fs);
  const ZonalBasis basis(8);
  for (double a : {0.0, 0.5, 1.2}) {
    const Vec3 n(0, 1, 0), wo(std::sin(a), std::cos(a), 0);
    const Rgb exact = shade_point(basis, set.materials[1], env, n, wo);
    const Rgb stored = shade_point(basis, half.materials[1], env, n, wo);
    EXPECT_LT(((stored - exact).abs() / exact).maxCoeff(), 1e-3) << a;
  }
}

TEST(CoefficientFile, ErrorsNameTheFile) {
  test::TempDir dir;
  const auto path = dir / "other.safetensors";
  SafetensorsWriter w;
  w.add_metadata("format", "something-else");
  w.declare("x", DType::F32, {1});
  w.begin(path);
  const float x = 1.0f;
  w.write(&x, 4);
  w.commit();
  try {
    read_coefficients(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("other.safetensors"), std::string::npos);
  }
  EXPECT_THROW(read_coefficients(dir / "missing.safetensors"), Error);
  CoefficientSet empty;
  EXPECT_THROW(write_coefficients(dir / "e.safetensors", empty, DType::F32), Error);
}

/// A file as version 1 wrote it (no lobes metadata, K values per theta_o sample), or with another
/// version string.
void write_old_file(const std::filesystem::path& path, const ZonalCoefficients& c, const std::string& version) {
  const ZonalBasis basis(c.bands);
  const auto T = static_cast<std::int64_t>(c.theta_o_count), K = static_cast<std::int64_t>(basis.size());
  SafetensorsWriter w;
  w.add_metadata("format", "matlas-zonal");
  w.add_metadata("version", version);
  w.add_metadata("bands", std::to_string(c.bands));
  w.add_metadata("theta_o_count", std::to_string(c.theta_o_count));
  w.add_metadata("theta_rows", "128");
  w.add_metadata("phi_columns", "256");
  w.add_metadata("names", "[\"plastic\"]");
  w.add_metadata("storage", "f32");
  w.add_metadata("storage_error", "0");
  w.declare("coefficients", DType::F32, {1, T, K, 3});
  w.begin(path);
  std::vector<float> v(c.values.begin(), c.values.end());
  w.write(std::span<const float>(v));
  w.commit();
}

TEST(CoefficientFile, VersionTwoKeepsTheLobesAndVersionOneStillReads) {
  test::TempDir dir;
  CoefficientSet set;
  set.settings.bands = 4;
  set.settings.theta_o_count = 4;
  set.settings.lobes = {64.0, 512.0};
  const ZonalProjector projector(set.settings);
  set.names = {"plastic"};
  set.materials.push_back(projector.project(tabulate(RoughPlastic{Rgb(0.5, 0.2, 0.1), 0.1, 1.5, 1.0})));
  write_coefficients(dir / "v2.safetensors", set, DType::F32);
  const CoefficientSet back = read_coefficients(dir / "v2.safetensors");
  EXPECT_EQ(back.settings.lobes, set.settings.lobes);
  ASSERT_EQ(back.materials[0].size(), 15u + 2u);
  EXPECT_EQ(back.materials[0].lobes, set.settings.lobes);
  for (std::size_t v = 0; v < set.materials[0].values.size(); ++v)
    EXPECT_NEAR(back.materials[0].values[v], set.materials[0].values[v], 1e-6 * std::abs(set.materials[0].values[v]) + 1e-9);

  // Version 1 (before the lobes): read as a set without lobes, values as written.
  ProjectionSettings plain = set.settings;
  plain.lobes.clear();
  const ZonalCoefficients old = ZonalProjector(plain).project(tabulate(RoughPlastic{Rgb(0.5, 0.2, 0.1), 0.1, 1.5, 1.0}));
  write_old_file(dir / "v1.safetensors", old, "1");
  const CoefficientSet v1 = read_coefficients(dir / "v1.safetensors");
  EXPECT_TRUE(v1.settings.lobes.empty());
  ASSERT_EQ(v1.materials[0].values.size(), old.values.size());
  EXPECT_NEAR(v1.materials[0].values[5], old.values[5], 1e-6 * std::abs(old.values[5]));

  // A newer version is refused, saying so.
  write_old_file(dir / "v3.safetensors", old, "3");
  try {
    read_coefficients(dir / "v3.safetensors");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("version 3 is newer"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace matlas::zonal
