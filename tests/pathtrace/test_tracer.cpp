// The path tracer against independent expectations: furnace tests (a convex white-ish object in a
// uniform environment shows albedo x radiance), a GGX sphere against a quadrature of the closed
// form, the split of the image into P, N z and I2, determinism.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "brdf/tabulate.h"
#include "core/check.h"
#include "core/error.h"
#include "formats/mesh_io.h"
#include "pathtrace/tracer.h"
#include "render/material.h"
#include "render/sampling.h"
#include "support/ortho_sphere.h"
#include "support/temp_dir.h"

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
  const render::TableMaterial material(table);
  const render::MaterialList bank({&material});
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

TEST(PathTracer, LambertianSphereUnderDirectionalLightIsAlbedoOverPiTimesCosine) {
  // No environment: the image is the directional light's next-event estimate (and the light's
  // bounces, none on a convex object), with no random numbers but the pixel jitter.
  SceneSpec s;
  s.camera.orthographic = true;
  s.camera.position = Vec3(0, 0, 5);
  s.camera.ortho_height = 2.2;
  const Vec3 light = Vec3(0.3, 0.5, 0.8).normalized();
  s.lights.push_back({3.0 * light, Rgb(2.0, 1.0, 0.5)});  // directions need not be unit
  ObjectSpec o;
  o.surface.albedo = Rgb(0.9, 0.6, 0.3);
  s.objects.push_back(o);
  TraceSettings settings;
  settings.width = settings.height = 48;
  settings.spp = 16;
  const Image image = trace(World(s), nullptr, settings).p;
  int checked = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const auto normal = test::ortho_sphere_normal(x, y, settings.width, settings.height);
      if (!normal) continue;  // away from the silhouette
      const Vec3 n = *normal;
      const double cos_theta = n.dot(light);
      if (std::abs(cos_theta) < 0.1) continue;  // and from the terminator
      ++checked;
      for (int c = 0; c < 3; ++c) {
        const double expected = o.surface.albedo[c] / kPi * s.lights[0].irradiance[c] * std::max(cos_theta, 0.0);
        EXPECT_NEAR(image.pixel(x, y)[c], expected, 0.01) << x << "," << y;
      }
    }
  EXPECT_GT(checked, 800);
}

TEST(PathTracer, AnInvisibleEnvironmentLightsTheSceneButIsNotSeen) {
  SurfaceSpec white;
  white.albedo = Rgb(0.8, 0.6, 0.4);
  SceneSpec s = sphere_scene(white, 0.7);
  s.camera.fov_degrees = 30.0;  // the sphere in the middle, the environment around it
  s.environment.visible = false;
  TraceSettings settings = small(1024);
  settings.width = settings.height = 15;
  const Image hidden = trace(World(s), nullptr, settings).p;
  s.environment.visible = true;
  const Image seen = trace(World(s), nullptr, settings).p;
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(hidden.pixel(0, 0)[c], 0.0f);
    EXPECT_NEAR(seen.pixel(0, 0)[c], 0.7, 1e-6);
    // The object is lit as before, by the same samples.
    EXPECT_EQ(hidden.pixel(7, 7)[c], seen.pixel(7, 7)[c]);
    EXPECT_NEAR(centre_mean(hidden, c), 0.7 * white.albedo[c], 1e-2 * white.albedo[c]) << c;
  }
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
  const render::TableMaterial material(table);
  const render::MaterialList bank({&material});
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
  const render::TableMaterial ma(a), mb(b);
  const render::MaterialList bank({&ma, &mb});
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
  const render::MaterialList only_b({&mb});
  const TraceImages r2 = trace(world, &only_b, t);
  EXPECT_EQ(r2.p.rgb, r.p.rgb);
  EXPECT_EQ(r2.once[0].rgb, r.once[1].rgb);
  EXPECT_EQ(r2.more[0].rgb, r.more[1].rgb);
}

/// An independent estimator of the same image: the plain path tracer that only follows cosine
/// samples of Lambertian surfaces and counts the environment when a path escapes (no next-event
/// estimation, MIS or roulette), with up to `max_depth` scattering vertices.
Image naive_lambert_trace(const World& world, int width, int height, int spp, int max_depth) {
  Image out(width, height);
  const std::uint64_t seed = 99;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Rgb sum = Rgb::Zero();
      const std::uint64_t pixel = static_cast<std::uint64_t>(y * width + x);
      for (int s = 0; s < spp; ++s) {
        render::SampleStream rng(seed, pixel, static_cast<std::uint64_t>(s));
        Vec3 origin, dir;
        world.camera_ray(x + rng.next(), y + rng.next(), width, height, &origin, &dir);
        Rgb beta = Rgb::Ones();
        for (int depth = 0;; ++depth) {
          const auto hit = world.intersect(origin, dir);
          if (!hit) {
            sum += beta.cwiseProduct(world.environment().eval(dir));
            break;
          }
          if (depth >= max_depth) break;
          beta = beta.cwiseProduct(world.object(hit->object).surface.albedo);  // f cos / pdf of cosine sampling
          Vec3 t, b;
          render::orthonormal_basis(hit->normal, t, b);
          const Vec3 l = render::sample_cosine(rng.next(), rng.next());
          dir = l.x() * t + l.y() * b + l.z() * hit->normal;
          origin = hit->position + 1e-4 * (1.0 + hit->position.cwiseAbs().maxCoeff()) * hit->geometric_normal;
        }
      }
      for (int c = 0; c < 3; ++c) out.pixel(x, y)[c] = static_cast<float>(sum[c] / spp);
    }
  return out;
}

TEST(PathTracer, InterreflectionsAgreeWithAPlainPathTracer) {
  // A grey sphere on a grey floor under a uniform sky: light reaches the floor under the sphere
  // and the sphere's lower half only after bounces, so next-event estimation at the second and
  // third vertices must carry the path's throughput (it once did not: those contributions were
  // as bright as direct light, the floor near objects glowed and glossy objects showed fireflies).
  SceneSpec s;
  s.camera.position = Vec3(0, 1.2, 4.5);
  s.camera.target = Vec3(0, 0.5, 0);
  s.camera.fov_degrees = 30;
  s.environment.constant = Rgb::Constant(1.0);
  ObjectSpec sphere;
  sphere.shape = "sphere";
  sphere.center = Vec3(0, 1, 0);
  sphere.radius = 1;
  sphere.surface.albedo = Rgb(0.7, 0.5, 0.3);
  ObjectSpec floor;
  floor.shape = "quad";
  floor.corner = Vec3(-20, 0, -20);
  floor.edge1 = Vec3(0, 0, 40);
  floor.edge2 = Vec3(40, 0, 0);
  floor.surface.albedo = Rgb(0.6, 0.6, 0.6);
  s.objects = {sphere, floor};
  const World world(s);
  TraceSettings t;
  t.width = 16;
  t.height = 12;
  t.spp = 1024;
  t.max_depth = 3;
  const Image traced = trace(world, nullptr, t).p;
  const Image naive = naive_lambert_trace(world, t.width, t.height, 2048, t.max_depth);
  // The darkest rows (the floor beside and under the sphere, the sphere's lower half) are where
  // bounces matter most: compare the bottom third of the image, and the whole.
  for (const int first_row : {0, 8}) {
    double a = 0, b = 0;
    for (int y = first_row; y < t.height; ++y)
      for (int x = 0; x < t.width; ++x)
        for (int c = 0; c < 3; ++c) {
          a += traced.pixel(x, y)[c];
          b += naive.pixel(x, y)[c];
        }
    EXPECT_NEAR(a / b, 1.0, 0.01) << "rows from " << first_row;
  }
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

TEST(Tracer, AMaterialIndexOutOfRangeIsACallersBug) {
  // The parts hold one image per material of the bank the trace used: asking for another is a
  // bug in matlas, refused by a check instead of reading past the end of `once`.
  TraceImages t;
  t.p = Image(2, 2);
  t.once.assign(1, Image(2, 2));
  t.more.assign(1, Image(2, 2));
  EXPECT_NO_THROW(t.full(0));
  EXPECT_THROW(t.i1(1), InternalError);
  EXPECT_THROW(t.full(-1), InternalError);
}

}  // namespace
}  // namespace matlas::pathtrace
