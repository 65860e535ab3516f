// Preview convergence at rest (docs/RENDERING.md "Refinement"): for named materials and midpoints
// of a model, the error of the refined preview against a long reference as a function of render
// samples and render time, for the refinement the server runs (render/progressive_render.h with the mixture fitted to
// the one material, as server/basis_previews.cpp does) and for the same passes with the database's
// mixture (the sampling of the preview bases). Prints one row per refine step and, per point and
// sampling, the samples and time to reach 2 % and 1 %. Samples do not depend on the machine's
// load; times do (the first line gives the load average).
//
//   bench_preview_convergence MODEL ENV SIZE REFERENCE_SPP MAX_SPP POINT...
//
// POINT is a material name or A+B (the latent midpoint of materials A and B). Errors are relative
// RMS over the pixels that see only the object, all channels, normalised by the reference's RMS
// there: sqrt(sum (image - reference)^2 / sum reference^2), with the reference's own error (its
// two-halves estimate) removed in quadrature. "estimated" is the refinement's own estimate
// (ProgressiveState::relative_error, the same normalisation), which the server reports.
// Time is the render time of the passes plus, for the first row, the table's build.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdlib.h>  // getloadavg
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "core/parallel.h"
#include "manifold/model.h"
#include "render/progressive_render.h"
#include "render/render.h"
#include "render/scene.h"

namespace {

using namespace matlas;

double relative_rms(const Image& a, const Image& reference, const std::vector<bool>& object) {
  double d = 0, s = 0;
  for (std::size_t p = 0; p < object.size(); ++p) {
    if (!object[p]) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = a.rgb[3 * p + c], r = reference.rgb[3 * p + c];
      d += (x - r) * (x - r);
      s += r * r;
    }
  }
  return std::sqrt(d / s);
}

int material_index(const Model& model, const std::string& name) {
  for (int i = 0; i < model.count(); ++i)
    if (model.names()[static_cast<std::size_t>(i)] == name) return i;
  std::fprintf(stderr, "no material %s in the model\n", name.c_str());
  std::exit(2);
}

Eigen::VectorXd point_of(const Model& model, const std::string& spec) {
  const auto plus = spec.find('+');
  if (plus == std::string::npos) return model.latent().row(material_index(model, spec)).transpose();
  const Eigen::VectorXd a = model.latent().row(material_index(model, spec.substr(0, plus))).transpose();
  const Eigen::VectorXd b = model.latent().row(material_index(model, spec.substr(plus + 1))).transpose();
  return 0.5 * (a + b);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 7) {
    std::fprintf(stderr, "usage: %s MODEL ENV SIZE REFERENCE_SPP MAX_SPP POINT...\n", argv[0]);
    return 2;
  }
  const Model model = Model::open(argv[1]);
  render::SceneDescription desc;
  desc.environment = argv[2];
  const auto scene = std::make_shared<const render::Scene>(desc);
  const int size = std::atoi(argv[3]), reference_spp = std::atoi(argv[4]);
  const int max_spp = std::atoi(argv[5]);

  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M", std::gmtime(&now));
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = -1;
  std::printf("# %s UTC, %d threads, load average %.1f, env %s, %dx%d, reference %d spp\n", date,
              static_cast<int>(worker_count()), load[0], argv[2], size, size, reference_spp);
  std::printf("%-44s %-8s %8s %7s %10s %10s\n", "point", "sampling", "seconds", "spp", "error", "estimated");

  render::RenderSettings base;
  base.width = base.height = size;
  base.spp = 16;
  const render::SamplingMixture database = atlas::model_render_settings(model, base).mixture;

  for (int a = 6; a < argc; ++a) {
    const std::string spec = argv[a];
    const Eigen::VectorXd w = model.weights(point_of(model, spec));
    const auto t0 = std::chrono::steady_clock::now();
    auto material = std::make_shared<const atlas::ModelTableMaterial>(model, w);
    const double table_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const render::SamplingMixture own = atlas::fit_sampling_mixture(
        render::MaterialList({material.get()}), atlas::SamplingFitOptions::for_sampler(base.sampler));

    render::ProgressiveSettings rs;
    rs.render = base;
    rs.render.mixture = own;
    rs.render.seed = 1000003;
    rs.max_spp = reference_spp;
    rs.target_error = 1e-12;
    render::ProgressiveRender reference(scene, material, rs);
    while (!reference.state().converged) reference.refine(60.0);
    const Image ref = reference.image();
    const double ref_error = reference.state().relative_error;
    std::printf("%-44s %-8s %8.2f %7d %10s %10.5f\n", spec.c_str(), "ref", reference.state().seconds, reference_spp, "-",
                ref_error);

    for (const bool fitted : {true, false}) {
      render::ProgressiveSettings s;
      s.render = base;
      s.render.mixture = fitted ? own : database;
      s.target_error = 1e-12;
      render::ProgressiveRender r(scene, material, s);
      double to2 = -1, to1 = -1;
      int spp2 = -1, spp1 = -1;
      while (r.state().spp < max_spp) {
        const render::ProgressiveState st = r.refine(0.25);
        const double measured = relative_rms(r.image(), ref, r.object_pixels());
        const double error = std::sqrt(std::max(0.0, measured * measured - ref_error * ref_error));
        const double t = st.seconds + table_seconds;
        if (to2 < 0 && error <= 0.02) to2 = t, spp2 = st.spp;
        if (to1 < 0 && error <= 0.01) to1 = t, spp1 = st.spp;
        std::printf("%-44s %-8s %8.2f %7d %10.5f %10.5f\n", spec.c_str(), fitted ? "own" : "database", t, st.spp, error,
                    st.relative_error);
      }
      std::printf("# %s, %s mixture: 2 %% at %d spp (%.1f s), 1 %% at %d spp (%.1f s); -1: not within %d spp\n",
                  spec.c_str(), fitted ? "own" : "database", spp2, to2, spp1, to1, max_spp);
      std::fflush(stdout);
    }
  }
  return 0;
}
