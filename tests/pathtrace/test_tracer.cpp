// The path tracer against independent expectations: furnace tests (a convex white-ish object in a
// uniform environment shows albedo x radiance), a GGX sphere against a quadrature of the closed
// form, the split of the image into P, N z and I2, determinism.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "brdf/tabulate.h"
#include "core/error.h"
#include "formats/mesh_io.h"
#include "support/temp_dir.h"
#include "pathtrace/tracer.h"

namespace matlas::pathtrace {
namespace {

SceneSpec sphere_scene(const SurfaceSpec& surface, double radiance) {
  SceneSpec s;
  s.camera.position = Vec3(0, 0, 10);
  s.camera.target = Vec3::Zero();
  s.camera.fov_degrees = 8.0;  // the sphere fills the frame; the centre pixel sees it head-on
  s.environment.constant = Rgb::Constant(radiance);
  ObjectSpec o;
  o.shape = "sphere";
  o.surface = surface;
  s.objects.push_back(o);
  return s;
}

/// Mean of channel c over the 3x3 centre pixels.
double centre_mean(const Image& im, int c) {
  double sum = 0;
  for (int y = im.height / 2 - 1; y <= im.height / 2 + 1; ++y)
    for (int x = im.width / 2 - 1; x <= im.width / 2 + 1; ++x) sum += im.pixel(x, y)[c];
  return sum / 9.0;
}

TraceSettings small(int spp) {
  TraceSettings t;
  t.width = t.height = 9;
  t.spp = spp;
  return t;
}

TEST(PathTracer, FurnaceLambertianSphereShowsAlbedoTimesRadiance) {
  SurfaceSpec white;
  white.albedo = Rgb(0.8, 0.6, 0.4);
  const World world(sphere_scene(white, 0.7));
  const TraceImages r = trace(world, nullptr, small(4096));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre_mean(r.p, c), 0.7 * white.albedo[c], 2e-3 * white.albedo[c]) << c;
}

TEST(PathTracer, FurnaceOnTheMeasuredObjectThroughTheFixedDensity) {
  // A tabulated Lambertian as the measured object: the whole image is N z (touched once), P and I2
  // vanish on the object (nothing else to see, convex), and N z = albedo x radiance.
  SurfaceSpec measured;
  measured.kind = SurfaceSpec::Kind::measured;
  const World world(sphere_scene(measured, 0.7));
  const BrdfTable table = tabulate([](const Vec3&, const Vec3&) -> Rgb { return Rgb(0.9, 0.5, 0.2) / kPi; });
  const TableListBank bank({&table});
  const TraceImages r = trace(world, &bank, small(4096));
  const Rgb albedo(0.9, 0.5, 0.2);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(centre_mean(r.once[0], c), 0.7 * albedo[c], 3e-3 * albedo[c]) << c;
    EXPECT_EQ(centre_mean(r.p, c), 0.0);
    EXPECT_EQ(centre_mean(r.more[0], c), 0.0);
  }
}

/// Directional albedo of a GGX lobe (F = 1, height-correlated Smith) at normal incidence, by
/// quadrature over theta_i of the closed-form D and Lambda (written here independently).
double ggx_albedo_at_normal_incidence(double alpha) {
  const int steps = 200000;
  double sum = 0;
  for (int i = 0; i < steps; ++i) {
    const double ti = (i + 0.5) * (kPi / 2) / steps;
    const double th = ti / 2;  // the half vector between wi and the normal
    const double t2h = std::tan(th) * std::tan(th), a2 = alpha * alpha;
    const double d = a2 / (kPi * std::pow(std::cos(th), 4) * (a2 + t2h) * (a2 + t2h));
    const double lambda_i = 0.5 * (std::sqrt(1 + a2 * std::tan(ti) * std::tan(ti)) - 1);
    const double g = 1.0 / (1.0 + lambda_i);  // Lambda(wo) = 0 at normal incidence
    const double f = d * g / (4 * std::cos(ti));
    sum += f * std::cos(ti) * std::sin(ti) * 2 * kPi;
  }
  return sum * (kPi / 2) / steps;
}

TEST(PathTracer, GgxSphereMatchesTheClosedForm) {
  SurfaceSpec ggx;
  ggx.kind = SurfaceSpec::Kind::ggx;
  ggx.albedo = Rgb::Zero();
  ggx.specular = Rgb::Ones();
  ggx.alpha = 0.3;
  const World world(sphere_scene(ggx, 1.0));
  const double expected = ggx_albedo_at_normal_incidence(0.3);
  EXPECT_GT(expected, 0.85);
  EXPECT_LT(expected, 1.0);
  const TraceImages r = trace(world, nullptr, small(2048));
  EXPECT_NEAR(centre_mean(r.p, 1), expected, 5e-3);
}

TEST(PathTracer, TabulatedGgxThroughTheFixedDensityMatchesTheClosedForm) {
  SurfaceSpec measured;
  measured.kind = SurfaceSpec::Kind::measured;
  const World world(sphere_scene(measured, 1.0));
  SurfaceSpec ggx;
  ggx.kind = SurfaceSpec::Kind::ggx;
  ggx.albedo = Rgb::Zero();
  ggx.specular = Rgb::Ones();
  ggx.alpha = 0.3;
  const BrdfTable table = tabulate([&](const Vec3& wi, const Vec3& wo) { return surface_eval(ggx, wi, wo); });
  const TableListBank bank({&table});
  const TraceImages r = trace(world, &bank, small(2048));
  // Nearest-bin lookup of a lobe of width 0.3 costs well under 1 %.
  EXPECT_NEAR(centre_mean(r.once[0], 1), ggx_albedo_at_normal_incidence(0.3), 1e-2);
}

TEST(PathTracer, ImagesSplitByTouchesAndAreDeterministic) {
  // The object on a floor under an area light and an environment: paths bounce between the two.
  const SceneSpec scene = load_scene("box", "sphere");
  const World world(scene);
  const BrdfTable a = tabulate([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.5 / kPi); });
  const BrdfTable b = tabulate([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(1.0 / kPi); });
  const TableListBank bank({&a, &b});
  TraceSettings t;
  t.width = t.height = 24;
  t.spp = 8;
  const TraceImages r = trace(world, &bank, t);
  // Doubling the BRDF doubles N z exactly and I2 at least fourfold (every term has >= 2 factors).
  double once_a = 0, once_b = 0, more_a = 0, more_b = 0, p = 0;
  for (std::size_t i = 0; i < r.p.rgb.size(); ++i) {
    once_a += r.once[0].rgb[i], once_b += r.once[1].rgb[i];
    more_a += r.more[0].rgb[i], more_b += r.more[1].rgb[i];
    p += r.p.rgb[i];
  }
  EXPECT_GT(p, 0);
  EXPECT_GT(once_a, 0);
  EXPECT_GT(more_a, 0);
  EXPECT_NEAR(once_b / once_a, 2.0, 1e-5);
  EXPECT_GE(more_b / more_a, 4.0 - 1e-5);
  // Same numbers for a single-material bank (the paths do not depend on the bank).
  const TableListBank only_b({&b});
  const TraceImages r2 = trace(world, &only_b, t);
  EXPECT_EQ(r2.p.rgb, r.p.rgb);
  EXPECT_EQ(r2.once[0].rgb, r.once[1].rgb);
  EXPECT_EQ(r2.more[0].rgb, r.more[1].rgb);
}

TEST(SceneSpec, MeshesCanRestOnAPlane) {
  const test::TempDir dir("matlas-pt-mesh");
  TriangleMesh tetra;
  tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  write_obj(dir / "t.obj", tetra);
  const nlohmann::json j = {{"objects", nlohmann::json::array({{{"shape", "mesh"}, {"mesh", (dir / "t.obj").string()},
                                                                 {"center", {0, 5, 0}}, {"rest_on", 0.25}}})}};
  const SceneSpec spec = parse_scene(j, "t.json");
  ASSERT_TRUE(spec.objects[0].rest_on.has_value());
  const World world(spec);
  // The lowest vertex is now at y = 0.25 (the mesh spans about 1.5 units there, centred on x = z = 0).
  bool below = false, above = false;
  for (double x = -1.5; x <= 1.5; x += 0.01) {
    below |= world.intersect(Vec3(x, 0.24, -10), Vec3(0, 0, 1)).has_value();
    above |= world.intersect(Vec3(x, 0.30, -10), Vec3(0, 0, 1)).has_value();
  }
  EXPECT_FALSE(below);
  EXPECT_TRUE(above);
}

TEST(SceneSpec, BuiltInScenesRoundTripAndBadFilesAreNamed) {
  for (const std::string& name : builtin_scenes()) {
    const SceneSpec s = load_scene(name, "sphere");
    const SceneSpec back = parse_scene(scene_to_json(s), "round trip");
    EXPECT_EQ(scene_to_json(back), scene_to_json(s)) << name;
  }
  const nlohmann::json bad = {{"objects", nlohmann::json::array({{{"shape", "cube"}}})}};
  try {
    parse_scene(bad, "x.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.json: objects[0].shape"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace matlas::pathtrace
