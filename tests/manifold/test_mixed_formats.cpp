// A database folder mixing MERL .binary and RGL .bsdf files builds into one map.
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "core/error.h"
#include "formats/rgl_bsdf.h"
#include "manifold/build.h"
#include "manifold/model.h"
#include "manifold/project.h"
#include "support/synthetic_rgl.h"
#include "support/error_of.h"
#include "support/temp_dir.h"
#include "synthetic_database.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

using test::error_of;

/// Two MERL tables and two RGL files (standard grid: RGL files resample onto it).
void write_mixed_folder(const fs::path& dir) {
  fs::create_directories(dir);
  write_merl(dir / "a_merl.binary", test::smooth_table(0.2, 0.3, MerlDims{}));
  write_merl(dir / "b_merl.binary", test::smooth_table(0.7, 0.9, MerlDims{}));
  test::SyntheticRgl s;
  s.scale = 0.05;
  write_tensor_file(dir / "c_rgl.bsdf", s.fields());
  s.scale = 0.02;
  write_tensor_file(dir / "d_rgl.bsdf", s.fields());
  std::ofstream(dir / "notes.txt") << "ignored";
}

TEST(MixedFormats, AFolderOfMerlAndRglFilesBuildsOneMap) {
  test::TempDir dir;
  write_mixed_folder(dir / "db");
  const MaterialSet set = MaterialSet::open({dir / "db"});
  ASSERT_EQ(set.size(), 4u);
  EXPECT_EQ(set.names(), (std::vector<std::string>{"a_merl", "b_merl", "c_rgl", "d_rgl"}));
  EXPECT_FALSE(set.resampled(0));
  EXPECT_TRUE(set.resampled(2));
  EXPECT_EQ(set.resampled_count(), 2u);
  EXPECT_EQ(set.ignored().size(), 1u);
  EXPECT_EQ(set.file(2).path(), dir / "db" / "c_rgl.bsdf");

  BuildOptions o;
  o.dim = 1;
  build_model(set, o, dir / "m.matlas");
  const Model m = Model::open(dir / "m.matlas");
  ASSERT_EQ(m.count(), 4);
  // Every input, the resampled ones included, is reproduced at its own latent point.
  for (int i = 0; i < m.count(); ++i) {
    const fs::path source = set.file(static_cast<std::size_t>(i)).path();
    const BrdfTable input = read_brdf(source);
    const BrdfTable at = m.table(m.weights(m.latent().row(i).transpose()));
    double e = 0, n = 0;
    for (std::size_t v = 0; v < input.size(); ++v) {
      if (!m.kept(v)) continue;
      const double d = at.stored()[v] - input.stored()[v];
      e += d * d;
      n += input.stored()[v] * input.stored()[v];
    }
    EXPECT_LT(std::sqrt(e / n), 1e-5) << source;
  }
  // A .bsdf file projects onto the map directly: it lands on its own material.
  const Projection p = project_material(m, read_brdf(dir / "db" / "c_rgl.bsdf"));
  EXPECT_EQ(p.nearest, 2);
  EXPECT_LT(p.relative_error, 1e-4);
}

TEST(MixedFormats, NamesAreUniqueAcrossFormatsAndAnisotropicFilesAreRefused) {
  test::TempDir dir;
  write_mixed_folder(dir / "db");
  write_merl(dir / "db" / "c_rgl.binary", test::smooth_table(0.5, 0.5, MerlDims{}));
  const std::string dup = error_of([&] { MaterialSet::open({dir / "db"}); });
  EXPECT_NE(dup.find("duplicate material name 'c_rgl'"), std::string::npos) << dup;

  test::SyntheticRgl s;
  s.phi_i = {-3.1415927f, -2.3561945f, -1.5707964f};
  write_tensor_file(dir / "aniso.bsdf", s.fields());
  const std::string e = error_of([&] { MaterialSet::open({dir / "db" / "a_merl.binary", dir / "aniso.bsdf"}); });
  EXPECT_NE(e.find("aniso.bsdf: anisotropic"), std::string::npos) << e;
  EXPECT_NE(e.find("not supported yet"), std::string::npos) << e;

  std::ofstream(dir / "broken.bsdf") << "tensor_file";
  const std::string b = error_of([&] { MaterialSet::open({dir / "db" / "a_merl.binary", dir / "broken.bsdf"}); });
  EXPECT_NE(b.find("broken.bsdf: "), std::string::npos) << b;
}

}  // namespace
}  // namespace matlas
