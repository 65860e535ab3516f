// One scene, two integrators: a preview's scene (render/scene.h) as a GI scene
// (pathtrace/preview_scene.h), seen by the same rays, and rendered by the previews' direct
// lighting (render::render) and by the path tracer restricted to direct lighting (max_depth 1)
// into the same image, within noise.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "brdf/analytic.h"
#include "core/atomic_file.h"
#include "pathtrace/preview_scene.h"
#include "pathtrace/tracer.h"
#include "render/material.h"
#include "render/render.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas::pathtrace {
namespace {

TEST(PreviewScene, IsAGiSceneThatRaysSeeTheSame) {
  const test::TempDir dir("matlas-preview-scene");
  // A tetrahedron: placed into the unit sphere, its lowest vertex carries the ground (above -1).
  write_file_atomic(dir / "tet.obj", "v 0 2 0\nv -1 0 -1\nv 1 0 -1\nv 0 0 1.5\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
  for (const std::string& object : {std::string("sphere"), (dir / "tet.obj").string()}) {
    render::SceneDescription d;
    d.object = object;
    d.ground = true;
    d.ground_albedo = Rgb(0.2, 0.3, 0.4);
    d.camera.position = Vec3(0.5, 1.5, 4.0);
    d.constant_radiance = Rgb(0.5, 0.6, 0.7);
    d.environment_intensity = 2.0;
    d.lights.push_back({Vec3(0.2, 1, 0.3), Rgb(3, 2, 1)});
    d.show_environment = false;
    const SceneSpec spec = preview_scene(d);
    ASSERT_EQ(spec.objects.size(), 2u);
    EXPECT_EQ(spec.objects[0].surface.kind, SurfaceSpec::Kind::measured);
    EXPECT_EQ(spec.objects[1].surface.kind, SurfaceSpec::Kind::lambert);
    EXPECT_EQ(spec.objects[1].surface.albedo.matrix(), d.ground_albedo.matrix());
    EXPECT_EQ(spec.objects[1].corner.y(), render::place_object(render::read_object(d)).ground[0].y());
    if (object == "sphere") EXPECT_EQ(spec.objects[1].corner.y(), -1.0);
    else EXPECT_GT(spec.objects[1].corner.y(), -1.0);
    EXPECT_EQ(spec.camera.position, d.camera.position);
    EXPECT_EQ(spec.camera.fov_degrees, d.camera.fov_degrees);
    EXPECT_EQ((spec.environment.constant * spec.environment.intensity).matrix(), (d.constant_radiance * 2.0).matrix());
    EXPECT_FALSE(spec.environment.visible);
    ASSERT_EQ(spec.lights.size(), 1u);
    EXPECT_EQ(spec.lights[0].direction, d.lights[0].direction);
    EXPECT_EQ(spec.lights[0].irradiance.matrix(), d.lights[0].irradiance.matrix());
    EXPECT_EQ(scene_to_json(parse_scene(scene_to_json(spec), "again")), scene_to_json(spec));
    const World world(spec);
    const render::Scene scene(d);
    int object_hits = 0, ground_hits = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        Vec3 o, dir_ray;
        scene.camera_ray(x + 0.5, y + 0.5, 24, 24, &o, &dir_ray);
        const auto a = scene.intersect(o, dir_ray);
        const auto b = world.intersect(o, dir_ray);
        ASSERT_EQ(a.has_value(), b.has_value()) << object << " pixel " << x << ", " << y;
        if (!a) continue;
        EXPECT_EQ(a->object, b->object == 0) << object << " pixel " << x << ", " << y;
        EXPECT_LT((a->position - b->position).norm(), 1e-5);
        EXPECT_LT((a->geometric_normal - b->geometric_normal).norm(), 1e-5);
        (a->object ? object_hits : ground_hits) += 1;
      }
    EXPECT_GT(object_hits, 20) << object;
    EXPECT_GT(ground_hits, 20) << object;
  }
  // Without a ground nothing is read: the environment map and the mesh are the world's to load.
  render::SceneDescription map;
  map.object = (dir / "tet.obj").string();
  map.environment = "studio";
  map.environment_rotation = 90;
  const SceneSpec spec = preview_scene(map);
  ASSERT_EQ(spec.objects.size(), 1u);
  EXPECT_EQ(spec.objects[0].shape, "mesh");
  EXPECT_EQ(spec.objects[0].mesh, map.object);
  EXPECT_EQ(spec.environment.map, "studio");
  EXPECT_EQ(spec.environment.rotation, 90.0);
  // What a scene file could not hold is refused, naming the key.
  render::SceneDescription bright;
  bright.ground = true;
  bright.ground_albedo = Rgb(1.5, 0.5, 0.5);
  EXPECT_EQ(test::error_of([&] { preview_scene(bright); }), "scene: objects[1].material.albedo must be in [0, 1]");
  render::SceneDescription negative;
  negative.lights.push_back({Vec3(0, 1, 0), Rgb(-1, 1, 1)});
  EXPECT_EQ(test::error_of([&] { preview_scene(negative); }), "scene: lights[0].irradiance must be in [0, 1e6]");
}

/// A preview's scene with everything direct lighting can show: the object on the ground, a
/// constant environment, a directional light casting the object's shadow, a black background.
render::SceneDescription lit_scene() {
  render::SceneDescription d;
  d.environment = "constant";
  d.constant_radiance = Rgb(0.35, 0.4, 0.5);
  d.lights.push_back({Vec3(0.6, 1.0, 0.5).normalized(), Rgb(2.5, 2.3, 2.0)});
  d.ground = true;
  d.ground_albedo = Rgb(0.6, 0.5, 0.4);
  d.camera.position = Vec3(0.0, 1.6, 4.2);
  d.camera.target = Vec3(0.0, -0.3, 0.0);
  d.camera.fov_degrees = 45.0;
  d.show_environment = false;
  return d;
}

/// How two renders of a region agree: per channel, the relative difference of the region's means
/// (the bias), and the mean absolute difference per pixel relative to the region's mean (the
/// noise, and any error that moves light within the region).
struct Agreement {
  double mean = 0, pixel = 0;
  int pixels = 0;
};

template <class InRegion>
Agreement agreement(const Image& reference, const Image& other, InRegion in_region) {
  Agreement a;
  for (int c = 0; c < 3; ++c) {
    double sum_r = 0, sum_o = 0, sum_abs = 0;
    int n = 0;
    for (int y = 0; y < reference.height; ++y)
      for (int x = 0; x < reference.width; ++x) {
        if (!in_region(x, y)) continue;
        const double r = reference.pixel(x, y)[c], o = other.pixel(x, y)[c];
        sum_r += r, sum_o += o, sum_abs += std::abs(r - o);
        ++n;
      }
    a.pixels = n;
    if (n == 0 || !(sum_r > 0)) return {1e9, 1e9, n};
    a.mean = std::max(a.mean, std::abs(sum_o - sum_r) / sum_r);
    a.pixel = std::max(a.pixel, sum_abs / sum_r);
  }
  return a;
}

TEST(PreviewScene, TheTwoIntegratorsAgreeOnDirectLighting) {
  const render::SceneDescription d = lit_scene();
  const render::Scene scene(d);
  const World world(preview_scene(d));
  render::RenderSettings preview;
  preview.width = 64;
  preview.height = 48;
  preview.spp = 64;
  TraceSettings direct;
  direct.width = preview.width;
  direct.height = preview.height;
  direct.spp = 256;
  direct.max_depth = 1;  // direct lighting: no bounce off the ground or the object
  const std::vector<float> coverage = render::object_coverage(scene, preview);
  const auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(preview.width) + static_cast<std::size_t>(x); };
  const auto ground = [&](int x, int y) {
    if (coverage[at(x, y)] != 0.0f) return false;
    Vec3 o, dir;
    scene.camera_ray(x + 0.5, y + 0.5, preview.width, preview.height, &o, &dir);
    // Within the light's reach: the ground's far part is dim and noisy.
    const auto hit = scene.intersect(o, dir);
    return hit && hit->position.norm() < 4.0;
  };

  const Lambertian diffuse{Rgb::Constant(0.5)};
  const GgxConductor glossy{Rgb(0.9, 0.7, 0.5), 0.2};
  for (const AnalyticBrdf& brdf : {AnalyticBrdf(diffuse), AnalyticBrdf(glossy)}) {
    const render::FunctionMaterial material([&](const Vec3& wi, const Vec3& wo) { return evaluate(brdf, wi, wo); });
    const Image a = render::render(scene, material, preview);
    const render::MaterialList bank({&material});
    const Image b = trace(world, &bank, direct).full(0);
    const std::string name = family_name(brdf);

    const Agreement object = agreement(a, b, [&](int x, int y) { return coverage[at(x, y)] == 1.0f; });
    EXPECT_GT(object.pixels, 400) << name;
    EXPECT_LT(object.mean, 0.01) << name;
    EXPECT_LT(object.pixel, 0.06) << name;
    const Agreement floor = agreement(a, b, ground);
    EXPECT_GT(floor.pixels, 1000) << name;
    EXPECT_LT(floor.mean, 0.01) << name;
    EXPECT_LT(floor.pixel, 0.04) << name;
    // The black background: nothing in either.
    int background = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        if (a.pixel(x, y)[0] == 0.0f && coverage[at(x, y)] == 0.0f) {
          ++background;
          EXPECT_EQ(b.pixel(x, y)[0], 0.0f) << name << " " << x << ", " << y;
        }
    EXPECT_GT(background, 40) << name;
    std::printf("%s: object %d pixels, means within %.4f, pixels %.4f; ground %d pixels, %.4f, %.4f; background %d\n",
                name.c_str(), object.pixels, object.mean, object.pixel, floor.pixels, floor.mean, floor.pixel, background);
  }
}

}  // namespace
}  // namespace matlas::pathtrace
