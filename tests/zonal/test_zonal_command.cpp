// `matlas zonal` on a folder: the file holds the library's projection of every table.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "formats/merl_file.h"
#include "support/temp_dir.h"
#include "zonal/coefficient_file.h"

namespace matlas::zonal {
namespace {

int run_matlas(const std::string& args) {
  return std::system((std::string(MATLAS_EXE) + " " + args + " > /dev/null 2>&1").c_str());
}

TEST(ZonalCommand, WritesTheCoefficientsOfAFolder) {
  test::TempDir dir;
  std::filesystem::create_directory(dir / "db");
  const BrdfTable a = tabulate(Lambertian{Rgb(0.2, 0.4, 0.6)});
  const BrdfTable b = tabulate(GgxConductor{Rgb(0.9, 0.9, 0.9), 0.3});
  write_merl(dir / "db/b-metal.binary", b);
  write_merl(dir / "db/a-matte.binary", a);
  const auto out = dir / "z.safetensors";
  ASSERT_EQ(run_matlas("zonal " + (dir / "db").string() + " -o " + out.string() + " --bands 4 --theta-o 4"), 0);
  const CoefficientSet set = read_coefficients(out);
  ASSERT_EQ(set.names, (std::vector<std::string>{"a-matte", "b-metal"}));
  EXPECT_FALSE(set.mean.has_value());
  ProjectionSettings s = set.settings;
  EXPECT_EQ(s.bands, 4);
  EXPECT_EQ(s.theta_o_count, 4);
  const ZonalProjector projector(s);
  const ZonalCoefficients expected = projector.project(b);
  for (std::size_t v = 0; v < expected.values.size(); ++v)
    EXPECT_NEAR(set.materials[1].values[v], expected.values[v], 1e-6 * (1 + std::abs(expected.values[v])));
  // With the viewer's lobes and ring floor: the projector's coefficients with the same settings.
  ASSERT_EQ(run_matlas("zonal " + (dir / "db").string() + " -o " + out.string() +
                       " --bands 4 --theta-o 4 --lobes default --ring-floor 0.05"),
            0);
  const CoefficientSet viewer = read_coefficients(out);
  EXPECT_EQ(viewer.settings.lobes, kDefaultLobes);
  EXPECT_EQ(viewer.settings.ring_floor, 0.05);
  const ZonalCoefficients limited = ZonalProjector(viewer.settings).project(b);
  for (std::size_t v = 0; v < limited.values.size(); ++v)
    EXPECT_NEAR(viewer.materials[1].values[v], limited.values[v], 1e-6 * (1 + std::abs(limited.values[v])));
  // A bad flag value is a usage error (2), a missing input a bad-input error (1).
  EXPECT_EQ(WEXITSTATUS(run_matlas("zonal " + (dir / "db").string() + " -o " + out.string() + " --bands 500")), 2);
  EXPECT_EQ(WEXITSTATUS(run_matlas("zonal " + (dir / "db").string() + " -o " + out.string() + " --lobes 64,x")), 2);
  EXPECT_EQ(WEXITSTATUS(run_matlas("zonal " + (dir / "db").string() + " -o " + out.string() + " --lobes 256,64")), 1);
  EXPECT_EQ(WEXITSTATUS(run_matlas("zonal " + (dir / "db").string() + " -o " + out.string() + " --lobes none,64")), 1);
  // One table is enough (no manifold is built): its coefficients as the projector's.
  ASSERT_EQ(run_matlas("zonal " + (dir / "db/b-metal.binary").string() + " -o " + out.string() + " --bands 4 --theta-o 4"), 0);
  const CoefficientSet one = read_coefficients(out);
  ASSERT_EQ(one.names, std::vector<std::string>{"b-metal"});
  for (std::size_t v = 0; v < expected.values.size(); ++v)
    EXPECT_NEAR(one.materials[0].values[v], expected.values[v], 1e-6 * (1 + std::abs(expected.values[v])));
  EXPECT_EQ(WEXITSTATUS(run_matlas("zonal " + (dir / "none").string() + " -o " + out.string())), 1);
}

}  // namespace
}  // namespace matlas::zonal
