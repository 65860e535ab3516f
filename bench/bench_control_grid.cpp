// The control grid's interpolation error (render/control_grid.h, docs/RENDERING.md "Control
// variate"): for every pixel the grid serves, 16 jittered camera samples compare the grid's
// bilinear value of the smooth integral G with G evaluated at the sample; the per-pixel means of
// the difference, RMS over the pixels relative to G's RMS, are the bias the grid leaves in a
// refined preview (the control variate's estimator is unbiased for the exact G).
//
//   bench_control_grid MODEL OBJECT MATERIAL        (studio, 256 x 256, the server's settings)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include "atlas/model_material.h"
#include "manifold/model.h"
#include "render/control_grid.h"
#include "render/render.h"
#include "render/scene.h"
#include "render/sampling.h"
#include "zonal/control_variate.h"
#include "zonal/projection.h"
using namespace matlas;
int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s MODEL OBJECT MATERIAL\n", argv[0]);
    return 2;
  }
  const Model model = Model::open(argv[1]);
  render::SceneDescription desc; desc.environment = "studio"; desc.object = argv[2];
  const auto scene = std::make_shared<const render::Scene>(desc);
  const Eigen::VectorXd w = model.material_weights(model.index_of(argv[3]));
  const atlas::ModelTableMaterial material(model, w);
  const auto prefiltered = std::make_shared<const zonal::PrefilteredEnvironment>(scene->environment(), zonal::control_prefilter_settings());
  const zonal::ZonalProjector projector(zonal::control_projection_settings());
  const zonal::ZonalControlVariate cv(projector.project(material.table()), prefiltered, -1);
  const int size = 256;
  const auto t0 = std::chrono::steady_clock::now();
  const render::ControlGrid grid = render::control_grid(*scene, size, size, cv);
  std::printf("grid %.3f s, %zu values\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), grid.values.size());
  double d2_one = 0, d2_cut = 0;
  double d2 = 0, s2 = 0, dsum = 0, ssum = 0; int used = 0, cells = 0;
  for (int y = 0; y < size; ++y) for (int x = 0; x < size; ++x) {
    const auto& cell = grid.cells[y * size + x];
    if (cell.subdivisions == 0) continue;
    ++cells;
    Rgb mean_d = Rgb::Zero(), mean_e = Rgb::Zero();
    for (int k = 0; k < 16; ++k) {
      render::SampleStream rng(7, y * size + x, k);
      const double jx = rng.next(), jy = rng.next();
      Vec3 o, d; scene->camera_ray(x + jx, y + jy, size, size, &o, &d);
      const auto hit = scene->intersect(o, d);
      if (!hit || !hit->object) continue;
      const Rgb exact = cv.smooth_integral(hit->normal, -d);
      const int s = cell.subdivisions;
      const double u = jx * s, v = jy * s;
      const int i = std::min(static_cast<int>(u), s - 1), j = std::min(static_cast<int>(v), s - 1);
      const double fx = u - i, fy = v - j;
      const Rgb* p = &grid.values[cell.offset + j * (s + 1) + i];
      const std::size_t row = s + 1;
      const Rgb interp = (1 - fy) * ((1 - fx) * p[0] + fx * p[1]) + fy * ((1 - fx) * p[row] + fx * p[row + 1]);
      mean_d += (interp - exact) / 16.0; mean_e += exact / 16.0; ++used;
    }
    (cell.subdivisions == 1 ? d2_one : d2_cut) += mean_d.square().sum();
    d2 += mean_d.square().sum(); s2 += mean_e.square().sum(); dsum += mean_d.sum(); ssum += mean_e.sum();
  }
  std::printf("%s %s: grid cells %d, per-pixel mean (grid - exact) RMS relative to G's RMS: %.4f %%, mean %.4f %%\n", argv[2], argv[3], cells,
              100 * std::sqrt(d2 / s2), 100 * dsum / ssum);
  std::printf("  of the squared error: one-cell pixels %.1f %%, cut pixels %.1f %%\n", 100 * d2_one / d2, 100 * d2_cut / d2);
}
