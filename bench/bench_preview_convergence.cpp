// Preview convergence at rest (docs/RENDERING.md "Refinement", "Control variate"): for named
// materials and midpoints of a model, the error of the refined preview against a long reference
// as a function of render samples and render time. "plain": the plain estimator with the
// server's sampling (render/progressive_render.h with the mixture fitted to the one material made
// defensive with the database's, atlas::defensive_mixture, as server/basis_previews.cpp does) and
// no adaptive sampling; "cv": the same with the real-time shading as a control variate
// (zonal/control_variate.h), tried on the second pass and kept (restarting the refinement) or
// dropped (the summary line says which), times including the projection and the grid; "served":
// the refinement as served, "cv" with adaptive sampling (render/adaptive_sampling.h: the trial
// pass also chooses each pixel's share of the samples); "own" and "database": the plain estimator
// with each of the two mixtures alone (fitted to the material;
// the preview bases' sampling). MATLAS_BENCH_SNAPSHOTS=DIR writes each point's image after about
// 3 s and its reference as PNG; MATLAS_BENCH_OBJECT=NAME renders that object instead of the sphere;
// MATLAS_BENCH_CV_BANDS, _CV_LOBES, _CV_TEXELS, _CV_LOBE_ROWS change the control variate's bands,
// lobes taking part, texels per band and sharpest lobe map's rows (the studies in RENDERING.md).
// MATLAS_BENCH_SERVER_ONLY=1: rows "plain", "cv" and "served" only (MATLAS_BENCH_ROWS=A,B: those). MATLAS_BENCH_NOISE_MAP=1: per
// point, where a uniform render's noise sits and what adaptive sampling gains (noise_map below).
// Prints one row per refine step and, per point and sampling, the samples and time to reach 2 %
// and 1 %. Samples do not depend on the machine's
// load; times do (the first line gives the load average).
//
//   bench_preview_convergence MODEL ENV SIZE REFERENCE_SPP MAX_SPP POINT...
//
// POINT is a material name or A+B (the latent midpoint of materials A and B). Errors are relative
// RMS over the pixels that see only the object, all channels, normalised by the reference's RMS
// there: sqrt(sum (image - reference)^2 / sum reference^2), with the reference's own error (its
// two-halves estimate) removed in quadrature. "estimated" is the refinement's own estimate
// (RefinementState::relative_error, the same normalisation), which the server reports.
// Time is the render time of the passes plus, for the first row, the table's build. "denoised" is
// the same image denoised from its two halves (ProgressiveRender::denoised, render/denoise.h:
// biased), its error against the reference, its own estimate and the denoiser's seconds.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdlib.h>  // getloadavg
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "formats/image_io.h"
#include "core/parallel.h"
#include "manifold/model.h"
#include "render/adaptive_sampling.h"
#include "render/progressive_render.h"
#include "render/render.h"
#include "render/scene.h"
#include "zonal/control_variate.h"
#include "zonal/projection.h"

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

/// The error as shown: RMS over the object's pixels and channels of the difference of the two
/// images tone mapped as the server's previews (ACES, exposure 0, sRGB), in 8-bit levels (not
/// quantised; the reference's own noise is left in).
double shown_rms(const Image& a, const Image& reference, const std::vector<bool>& object) {
  const auto shown = [](float v) { return 255.0 * srgb_encode(std::min(1.0f, tone_curve(v, 1.0f, ToneMap::Curve::aces))); };
  double d = 0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < object.size(); ++p) {
    if (!object[p]) continue;
    for (std::size_t c = 0; c < 3; ++c, ++n) {
      const double x = shown(a.rgb[3 * p + c]) - shown(reference.rgb[3 * p + c]);
      d += x * x;
    }
  }
  return n ? std::sqrt(d / static_cast<double>(n)) : 0.0;
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

/// MATLAS_BENCH_NOISE_MAP=1: where the noise of a uniform 16-spp render sits, and what adaptive
/// sampling's shares gain at equal samples. Two pairs of renders (4 seeds): the per-pixel variance
/// of one render is (a - b)^2 / 2 per pair; the shares come from pair 1 (adaptive_pixel_samples,
/// the defaults), the gain is pair 2's variance summed over the pixels divided by the same with
/// each pixel's divided by its share (the variance with spp x share samples there).
void noise_map(const render::Scene& scene, const render::Material& material, render::RenderSettings s,
               const render::SamplingMixture& mixture, const std::string& spec) {
  s.mixture = mixture;
  s.spp = 16;
  Image im[4];
  for (int k = 0; k < 4; ++k) {
    s.seed = 31337 + static_cast<std::uint64_t>(k);
    im[k] = render::render(scene, material, s);
  }
  const std::size_t n = im[0].pixel_count();
  const auto variance = [&](const Image& a, const Image& b) {
    std::vector<double> v(n, 0.0);
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t c = 0; c < 3; ++c) {
        const double d = static_cast<double>(a.rgb[3 * p + c]) - b.rgb[3 * p + c];
        v[p] += 0.5 * d * d;
      }
    return v;
  };
  const std::vector<double> v2 = variance(im[2], im[3]);
  std::vector<double> sorted = v2;
  std::sort(sorted.rbegin(), sorted.rend());
  const double total = std::accumulate(sorted.begin(), sorted.end(), 0.0);
  const auto top = [&](double fraction) {
    const auto end = sorted.begin() + static_cast<std::ptrdiff_t>(fraction * static_cast<double>(n));
    return std::accumulate(sorted.begin(), end, 0.0) / total;
  };
  // The same pair's variance as shown (ACES, sRGB).
  const auto shown_image = [&](const Image& x) {
    Image out = x;
    for (float& v : out.rgb) v = srgb_encode(std::min(1.0f, tone_curve(v, 1.0f, ToneMap::Curve::aces)));
    return out;
  };
  const std::vector<double> s2 = variance(shown_image(im[2]), shown_image(im[3]));
  const double shown_total = std::accumulate(s2.begin(), s2.end(), 0.0);
  const std::vector<int> counts = render::sample_counts(scene, s);
  std::vector<int> pair(counts.size());
  for (std::size_t p = 0; p < n; ++p) pair[p] = 2 * counts[p];
  std::vector<bool> all(n, true);
  Image mean = im[0];
  for (std::size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] = 0.5f * (im[0].rgb[i] + im[1].rgb[i]);
  std::printf("# %s noise map (16 spp, uniform): top 0.1 %% of pixels %.1f %% of the variance, top 1 %% %.1f %%, top 10 %% %.1f %%\n",
              spec.c_str(), 100 * top(0.001), 100 * top(0.01), 100 * top(0.1));
  for (const bool weighted : {false, true}) {
    const std::vector<double> weights =
        weighted ? render::linear_and_shown_weights(mean, all, ToneMap{ToneMap::Curve::aces, 0.0}) : std::vector<double>{};
    const std::vector<double> shares = render::adaptive_pixel_samples(im[0], im[1], pair, {}, weights);
    double adapted = 0, shown_adapted = 0;
    for (std::size_t p = 0; p < n; ++p) adapted += v2[p] / shares[p], shown_adapted += s2[p] / shares[p];
    std::printf("#   shares from another pair, %s: %.2fx less variance at equal samples, %.2fx as shown (largest share %.1f)\n",
                weighted ? "linear and shown" : "linear error", total / adapted, shown_total / shown_adapted,
                *std::max_element(shares.begin(), shares.end()));
  }
  std::fflush(stdout);
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
  if (const char* object = std::getenv("MATLAS_BENCH_OBJECT")) desc.object = object;  // default: the sphere
  const auto scene = std::make_shared<const render::Scene>(desc);
  const int size = std::atoi(argv[3]), reference_spp = std::atoi(argv[4]);
  const int max_spp = std::atoi(argv[5]);
  const bool only_server = std::getenv("MATLAS_BENCH_SERVER_ONLY") != nullptr;

  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M", std::gmtime(&now));
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = -1;
  std::printf("# %s UTC, %d threads, load average %.1f, env %s, %dx%d, reference %d spp\n", date,
              static_cast<int>(worker_count()), load[0], argv[2], size, size, reference_spp);
  std::printf("%-44s %-8s %8s %7s %10s %10s %10s %10s %8s %8s\n", "point", "sampling", "seconds", "spp", "error", "estimated",
              "denoised", "d.estim.", "d.sec", "shown");

  // MATLAS_BENCH_CV_BANDS / MATLAS_BENCH_CV_LOBES: the control variate's bands and lobes.
  // MATLAS_BENCH_CV_TEXELS / MATLAS_BENCH_CV_LOBE_ROWS: its environment's tabulation.
  zonal::ProjectionSettings projection = zonal::control_projection_settings();
  zonal::PrefilterSettings prefilter = zonal::control_prefilter_settings();
  if (const char* b = std::getenv("MATLAS_BENCH_CV_BANDS")) projection.bands = prefilter.bands = std::atoi(b);
  const int cv_lobes = std::getenv("MATLAS_BENCH_CV_LOBES") ? std::atoi(std::getenv("MATLAS_BENCH_CV_LOBES")) : -1;
  if (const char* t = std::getenv("MATLAS_BENCH_CV_TEXELS")) prefilter.texels_per_band = std::atof(t);
  if (const char* r = std::getenv("MATLAS_BENCH_CV_LOBE_ROWS")) prefilter.lobe_rows = std::atoi(r);
  const auto p0 = std::chrono::steady_clock::now();
  const auto prefiltered = std::make_shared<const zonal::PrefilteredEnvironment>(scene->environment(), prefilter);
  const double prefilter_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();

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
    rs.limits.max_spp = reference_spp;
    rs.limits.target_error = 1e-12;
    // The reference: the plain estimator with adaptive sampling (unbiased; its own noise, removed
    // below in quadrature, is then a tenth of a uniform reference's for chrome-like highlights).
    // MATLAS_BENCH_REFERENCE_CACHE=DIR keeps the references (EXR + error) for later runs.
    Image ref;
    double ref_error = 0;
    const char* cache_dir = std::getenv("MATLAS_BENCH_REFERENCE_CACHE");
    const std::string cache = cache_dir == nullptr ? std::string()
                                                   : std::string(cache_dir) + "/" + spec + "-" + argv[2] + "-" +
                                                         std::to_string(size) + "-" + std::to_string(reference_spp);
    if (!cache.empty() && std::filesystem::exists(cache + ".exr")) {
      ref = read_image(cache + ".exr");
      std::ifstream(cache + ".txt") >> ref_error;
      std::printf("%-44s %-8s %8s %7d %10s %10.5f\n", spec.c_str(), "ref", "cached", reference_spp, "-", ref_error);
    } else {
      render::ProgressiveRender reference(scene, material, rs);
      while (!reference.state().converged) reference.refine(60.0);
      ref = reference.image();
      ref_error = reference.state().relative_error;
      std::printf("%-44s %-8s %8.2f %7d %10s %10.5f\n", spec.c_str(), "ref", reference.state().seconds, reference_spp,
                  "-", ref_error);
      if (!cache.empty()) {
        write_exr(cache + ".exr", ref);
        std::ofstream(cache + ".txt") << ref_error << "\n";
      }
    }
    std::fflush(stdout);

    const render::SamplingMixture defensive = atlas::defensive_mixture(own, database);
    if (std::getenv("MATLAS_BENCH_NOISE_MAP") != nullptr) noise_map(*scene, *material, base, defensive, spec);
    // The control variate (zonal/control_variate.h): the point's rotated-ZH coefficients and the
    // environment prefiltered as the real-time view has them.
    const zonal::ZonalProjector projector(projection);
    std::printf("# %s: prefilter %.2f s (once per environment)\n", spec.c_str(), prefilter_seconds);
    for (const char* sampling : {"plain", "cv", "served", "own", "database"}) {
      const std::string which = sampling;
      if (only_server && which != "plain" && which != "cv" && which != "served") continue;
      if (const char* rows = std::getenv("MATLAS_BENCH_ROWS"); rows && ("," + std::string(rows) + ",").find("," + which + ",") == std::string::npos)
        continue;
      render::ProgressiveSettings s;
      s.render = base;
      s.render.mixture = which == "own" ? own : which == "database" ? database : defensive;
      s.adaptive.enabled = which == "served";  // adaptive sampling (render/adaptive_sampling.h)
      if (which == "cv" || which == "served")  // the projection runs in the second pass, as the server's
        s.control_variate = [&] {
          return std::make_shared<const zonal::ZonalControlVariate>(projector.project(material->table()), prefiltered,
                                                                    cv_lobes);
        };
      s.limits.target_error = 1e-12;
      // Setup (the coverage) counted in the first row's time as the server spends it; the
      // control variate's projection and grid are inside the second pass.
      const auto c0 = std::chrono::steady_clock::now();
      render::ProgressiveRender r(scene, material, s);
      const double setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
      double to2 = -1, to1 = -1, dto2 = -1, dto1 = -1;
      int spp2 = -1, spp1 = -1, dspp2 = -1, dspp1 = -1;
      bool snapped = false;
      while (r.state().spp < max_spp) {
        const render::RefinementState st = r.refine(0.25);
        const double measured = relative_rms(r.image(), ref, r.object_pixels());
        const double error = std::sqrt(std::max(0.0, measured * measured - ref_error * ref_error));
        const double t = st.seconds + table_seconds + setup_seconds;
        if (to2 < 0 && error <= 0.02) to2 = t, spp2 = st.spp;
        if (to1 < 0 && error <= 0.01) to1 = t, spp1 = st.spp;
        // The denoised image (render/denoise.h), its error against the reference and its cost.
        const auto d0 = std::chrono::steady_clock::now();
        const render::DenoiseResult den = r.denoised();
        const double dsec = std::chrono::duration<double>(std::chrono::steady_clock::now() - d0).count();
        const double dmeasured = relative_rms(den.image, ref, r.object_pixels());
        const double derror = std::sqrt(std::max(0.0, dmeasured * dmeasured - ref_error * ref_error));
        if (dto2 < 0 && derror <= 0.02) dto2 = t + dsec, dspp2 = st.spp;
        if (dto1 < 0 && derror <= 0.01) dto1 = t + dsec, dspp1 = st.spp;
        // MATLAS_BENCH_SNAPSHOTS=DIR: the image as served after about 3 s (the first row past it),
        // tone mapped as the server's previews (ACES), and the reference.
        if (const char* dir = std::getenv("MATLAS_BENCH_SNAPSHOTS"); dir && !snapped && t >= 3.0) {
          snapped = true;
          std::filesystem::create_directories(dir);
          const ToneMap aces{ToneMap::Curve::aces, 0.0};
          write_png(std::string(dir) + "/" + spec + "-" + sampling + "-3s.png", r.image(), aces);
          write_png(std::string(dir) + "/" + spec + "-reference.png", ref, aces);
        }
        std::printf("%-44s %-8s %8.2f %7d %10.5f %10.5f %10.5f %10.5f %8.3f %8.3f\n", spec.c_str(), sampling, t, st.spp, error,
                    st.relative_error, derror, den.relative_error, dsec, shown_rms(r.image(), ref, r.object_pixels()));
        std::fflush(stdout);
        // MATLAS_BENCH_DENOISE_SWEEP=1: the denoiser's settings over a grid at 32, 64, 128 and 256 spp.
        if (std::getenv("MATLAS_BENCH_DENOISE_SWEEP") != nullptr && (st.spp == 32 || st.spp == 64 || st.spp == 128 || st.spp == 256)) {
          for (int search : {4, 6, 9, 12})
            for (int patch : {1, 2})
              for (double strength : {0.45, 1.0, 1.5, 2.5}) {
                render::DenoiseSettings ds;
                ds.search_radius = search;
                ds.patch_radius = patch;
                ds.strength = strength;
                const double m = relative_rms(r.denoised(ds).image, ref, r.object_pixels());
                std::printf("sweep %s %d spp  search %2d patch %d strength %.2f  error %.5f\n", spec.c_str(), st.spp,
                            search, patch, strength, std::sqrt(std::max(0.0, m * m - ref_error * ref_error)));
              }
          std::fflush(stdout);
        }
      }
      std::printf("# %s, %s mixture: 2 %% at %d spp (%.1f s), 1 %% at %d spp (%.1f s); -1: not within %d spp%s\n",
                  spec.c_str(), sampling, spp2, to2, spp1, to1, max_spp,
                  which != "cv" && which != "served" ? "" : r.controlled() ? " (control variate chosen)" : " (plain estimator chosen)");
      std::printf("# %s, %s mixture, denoised: 2 %% at %d spp (%.1f s), 1 %% at %d spp (%.1f s)\n", spec.c_str(), sampling,
                  dspp2, dto2, dspp1, dto1);
      std::fflush(stdout);
    }
  }
  return 0;
}
