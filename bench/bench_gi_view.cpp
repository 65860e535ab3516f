// The scene view at rest (docs/GI.md, issue 25): how fast the refined GI image of a map point
// converges, and how far the composed image of the drag is from the truth (fireflies).
//
//   bench_gi_view MODEL SCENE OBJECT MATERIAL_A MATERIAL_B SECONDS REF_SPP [OUT_DIR]
//
// The point: midway between the two materials' latent points (the same name twice: the material).
// 1. Reference: a 512 x 384 trace of m(x) with REF_SPP paths per pixel (seed 777).
// 2. Refinement: pathtrace::ProgressiveTrace at 512 x 384 (the server's GiScenes::refine), refined
//    in steps of one second for SECONDS of wall time; per step the wall and CPU seconds, spp, the
//    estimated error and the error against the reference: relative L1 (sum |a - b| / sum |b| over
//    pixels and channels) and relative RMS. The reference's own noise is in these figures; its
//    share is given: the same error of the reference's two halves scaled to its full spp.
// 3. The drag: a 256 x 192, 16-spp basis (the server's default) composed at x against a
//    reference at that size (REF_SPP): relative L1 and the pixels whose luminance exceeds 20x the
//    reference's (among pixels at least 1 % of the image's mean luminance; darker ones counted
//    apart).
// Also the machine's load average at the start and end (a shared machine: CPU time is the figure
// that travels). OUT_DIR gets PNGs (auto exposure, ACES): reference, refined at 5 s / 30 s, composed
// (and composed-filtered, its fireflies removed as served).
// MATLAS_BENCH_ADAPTIVE=1 refines with adaptive sampling (the server's refinement has none);
// MATLAS_BENCH_NO_DRAG=1 skips part 3; MATLAS_BENCH_MIRROR_PROBABILITY=p traces with another
// TraceSettings::mirror_probability; MATLAS_BENCH_REFERENCE=PREFIX keeps the 512 x 384 reference's
// halves in PREFIX-a.exr / PREFIX-b.exr (read when they exist: a long reference made once);
// MATLAS_BENCH_SERVED=1 denoises after every step as the server does (its time counted in the
// refinement's; steps of 1 s, from 5 s on 2 s, as the page asks them) and MATLAS_BENCH_DENOISE=k:r:f,... tries other denoiser settings at 5 s and at the
// end (ProgressiveTrace::denoised; the served pathtrace::scene_denoise_settings() by default).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "atlas/gi_basis.h"
#include "atlas/gi_density.h"
#include "atlas/model_material.h"
#include "formats/image_io.h"
#include "manifold/model.h"
#include "pathtrace/progressive_trace.h"
#include "render/auto_exposure.h"
#include "render/denoise.h"
#include "render/firefly_filter.h"

namespace {

using namespace matlas;
using namespace matlas::atlas;
using namespace matlas::pathtrace;

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double load_average() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

double lum(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

struct Errors {
  double l1 = 0, rms = 0;
  int over20 = 0, over20_dark = 0;
  double max_ratio = 0;
};

Errors compare(const Image& a, const Image& ref) {
  Errors e;
  double d = 0, s = 0, d2 = 0, s2 = 0, mean = 0;
  const int pixels = ref.width * ref.height;
  for (int i = 0; i < pixels; ++i) mean += lum(&ref.rgb[3 * static_cast<std::size_t>(i)]) / pixels;
  for (std::size_t i = 0; i < ref.rgb.size(); ++i) {
    const double diff = static_cast<double>(a.rgb[i]) - ref.rgb[i];
    d += std::abs(diff), s += std::abs(static_cast<double>(ref.rgb[i]));
    d2 += diff * diff, s2 += static_cast<double>(ref.rgb[i]) * ref.rgb[i];
  }
  for (int i = 0; i < pixels; ++i) {
    const double la = lum(&a.rgb[3 * static_cast<std::size_t>(i)]), lr = lum(&ref.rgb[3 * static_cast<std::size_t>(i)]);
    const bool dark = lr < 0.01 * mean;
    if (la > 20 * lr) ++(dark ? e.over20_dark : e.over20);
    if (!dark) e.max_ratio = std::max(e.max_ratio, la / lr);
  }
  e.l1 = d / s;
  e.rms = std::sqrt(d2 / s2);
  return e;
}

void write_png(const std::string& dir, const std::string& name, const Image& image, double exposure) {
  if (dir.empty()) return;
  write_image(std::filesystem::path(dir) / name, image, ToneMap{ToneMap::Curve::aces, exposure});
}

/// The error against the truth: the RMS against the reference with the reference's own noise
/// taken out in quadrature (the two are independent).
double without_reference_noise(double rms, double reference_rms) {
  return std::sqrt(std::max(0.0, rms * rms - reference_rms * reference_rms));
}

/// The denoiser's settings: the served ones (pathtrace::scene_denoise_settings) or those of
/// MATLAS_BENCH_DENOISE=k:r:f,... (strength, search radius, patch radius).
std::vector<render::DenoiseSettings> denoise_settings_tried() {
  std::vector<render::DenoiseSettings> tried = {scene_denoise_settings()};
  if (const char* list = std::getenv("MATLAS_BENCH_DENOISE")) {
    tried.clear();
    std::string text = list;
    for (std::size_t start = 0; start < text.size();) {
      const std::size_t end = std::min(text.find(',', start), text.size());
      render::DenoiseSettings d;
      double k = 0;
      int r = 0, f = 0;
      if (std::sscanf(text.substr(start, end - start).c_str(), "%lf:%d:%d", &k, &r, &f) == 3) {
        d.strength = k, d.search_radius = r, d.patch_radius = f;
        tried.push_back(d);
      }
      start = end + 1;
    }
  }
  return tried;
}

/// The refinement as it stands, plain and denoised (ProgressiveTrace::denoised, biased) with each
/// of `tried`, against the reference.
void report_denoised(const ProgressiveTrace& refine, const std::vector<render::DenoiseSettings>& tried,
                     const Image& reference, double reference_rms, const std::string& dir, const std::string& name,
                     double exposure) {
  const Errors plain = compare(refine.image(), reference);
  std::printf("  %s, %d spp: plain L1 %.4f, RMS %.4f (%.4f without the reference's noise)\n", name.c_str(),
              refine.state().spp, plain.l1, plain.rms, without_reference_noise(plain.rms, reference_rms));
  for (const render::DenoiseSettings& d : tried) {
    const auto t = std::chrono::steady_clock::now();
    const render::DenoiseResult r = refine.denoised(d);
    const double took = seconds_since(t);
    const Errors e = compare(r.image, reference);
    std::printf("  denoised k %.2f, search %d, patch %d (%.2f s): L1 %.4f, RMS %.4f (%.4f without the reference's "
                "noise), estimated noise left %.4f\n",
                d.strength, d.search_radius, d.patch_radius, took, e.l1, e.rms,
                without_reference_noise(e.rms, reference_rms), r.relative_error);
    if (&d == &tried.front()) write_png(dir, name + "-denoised.png", r.image, exposure);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 8) {
    std::fprintf(stderr, "usage: %s MODEL SCENE OBJECT MATERIAL_A MATERIAL_B SECONDS REF_SPP [OUT_DIR]\n", argv[0]);
    return 2;
  }
  try {
    const double load_start = load_average();
    const Model model = Model::open(argv[1]);
    auto world = std::make_shared<const World>(load_scene(argv[2], argv[3]));
    const std::string out = argc > 8 ? argv[8] : "";
    if (!out.empty()) std::filesystem::create_directories(out);
    const Eigen::VectorXd x =
        0.5 * (model.latent().row(model.index_of(argv[4])) + model.latent().row(model.index_of(argv[5]))).transpose();
    const Eigen::VectorXd w = model.weights(x);
    const double seconds = std::stod(argv[6]);
    const int ref_spp = std::stoi(argv[7]);
    TraceSettings base;
    base.density = fit_gi_density(model);
    if (const char* m = std::getenv("MATLAS_BENCH_MIRROR_PROBABILITY")) base.mirror_probability = std::stod(m);
    const auto bank = atlas::model_point_bank(model, w);
    std::printf("scene %s/%s, point %s | %s, n = %d, load average %.1f (2-core machine, shared)\n", argv[2], argv[3],
                argv[4], argv[5], model.count(), load_start);

    // 1. References.
    TraceSettings ref = base;
    ref.width = 512, ref.height = 384, ref.spp = ref_spp / 2, ref.seed = 777;
    auto t0 = std::chrono::steady_clock::now();
    double c0 = cpu_seconds();
    // MATLAS_BENCH_REFERENCE=PREFIX: the reference's halves are read from PREFIX-a.exr and
    // PREFIX-b.exr when both exist (a long reference made once), else traced and written there.
    const char* cached = std::getenv("MATLAS_BENCH_REFERENCE");
    const std::string prefix = cached ? cached : "";
    Image reference, half_b;
    const bool read = !prefix.empty() && std::filesystem::exists(prefix + "-a.exr") && std::filesystem::exists(prefix + "-b.exr");
    if (read) {
      reference = read_image(prefix + "-a.exr");
      half_b = read_image(prefix + "-b.exr");
    } else {
      reference = trace(*world, bank.get(), ref).full(0);
      ref.seed = 778;
      half_b = trace(*world, bank.get(), ref).full(0);
      if (!prefix.empty()) {
        write_exr(prefix + "-a.exr", reference);
        write_exr(prefix + "-b.exr", half_b);
      }
    }
    const Image half_a = reference;
    for (std::size_t i = 0; i < reference.rgb.size(); ++i) reference.rgb[i] = 0.5f * (reference.rgb[i] + half_b.rgb[i]);
    // The reference's own error: its halves differ by sqrt(2) x the error of one half, which is
    // sqrt(2) x the error of the whole: the whole's error is |A - B| / 2.
    const Errors halves = compare(half_a, half_b);
    if (read)
      std::printf("reference 512x384 read from %s-{a,b}.exr; its own error about L1 %.4f, RMS %.4f\n", prefix.c_str(),
                  halves.l1 / 2, halves.rms / 2);
    else
      std::printf("reference 512x384, %d spp: %.0f s wall, %.0f s CPU; its own error about L1 %.4f, RMS %.4f\n", ref_spp,
                  seconds_since(t0), cpu_seconds() - c0, halves.l1 / 2, halves.rms / 2);
    const double exposure = render::auto_exposure(reference);
    write_png(out, "reference.png", reference, exposure);

    // 2. Refinement at rest.
    ProgressiveTraceSettings ps;
    ps.trace = base;
    ps.trace.width = 512, ps.trace.height = 384, ps.trace.spp = 1;
    ps.limits.max_spp = 1 << 20;
    ps.limits.target_error = 1e-6;  // never converged: the curve runs for SECONDS
    // MATLAS_BENCH_ADAPTIVE=1: with adaptive sampling (render/adaptive_sampling.h; the server's is off).
    ps.adaptive.enabled = std::getenv("MATLAS_BENCH_ADAPTIVE") != nullptr;
    std::printf("refinement: %s\n", ps.adaptive.enabled ? "adaptive sampling" : "uniform samples (as served)");
    ProgressiveTrace refine(world, bank, ps);
    std::printf("\n| wall s | CPU s | spp | estimated error (RMS) | L1 vs reference | RMS vs reference | pixels > 20x |\n|---:|---:|---:|---:|---:|---:|---:|\n");
    t0 = std::chrono::steady_clock::now();
    c0 = cpu_seconds();
    bool wrote5 = false;
    // MATLAS_BENCH_SERVED=1: as the server answers the browser, the image denoised after every
    // step (with the first of `tried`), its time in the refinement's, the steps as the page asks.
    const bool served = std::getenv("MATLAS_BENCH_SERVED") != nullptr;
    const std::vector<render::DenoiseSettings> tried = denoise_settings_tried();
    Image last_denoised;
    while (seconds_since(t0) < seconds) {
      // Steps as the page asks them when served: 1 s, then 2 s from 5 s of rest on (web/src/gi-view.ts).
      const double step = served && seconds_since(t0) >= 5 ? 2.0 : 1.0;
      const render::RefinementState st = refine.refine(std::min(step, std::max(0.05, seconds - seconds_since(t0))));
      if (served) last_denoised = refine.denoised(tried.front()).image;
      const Image im = refine.image();
      const Errors e = compare(im, reference);
      std::printf("| %.1f | %.1f | %d | %.4f | %.4f | %.4f | %d |\n", seconds_since(t0), cpu_seconds() - c0, st.spp,
                  st.relative_error, e.l1, e.rms, e.over20);
      std::fflush(stdout);
      if (!wrote5 && seconds_since(t0) >= 5) {
        write_png(out, "refined-5s.png", im, exposure);
        const auto r0 = std::chrono::steady_clock::now();
        const double rc0 = cpu_seconds();
        report_denoised(refine, tried, reference, halves.rms / 2, out, "refined-5s", exposure);
        t0 += std::chrono::steady_clock::now() - r0;  // (the report's time is not the refinement's)
        c0 += cpu_seconds() - rc0;
        wrote5 = true;
      }
    }
    write_png(out, "refined-end.png", refine.image(), exposure);
    if (served && seconds > 0) {
      const Errors e = compare(last_denoised, reference);
      std::printf("  served: the last image denoised within %.1f s, %d spp: L1 %.4f, RMS %.4f (%.4f without the "
                  "reference's noise)\n", seconds_since(t0), refine.state().spp, e.l1, e.rms,
                  without_reference_noise(e.rms, halves.rms / 2));
    }
    if (seconds > 0) report_denoised(refine, tried, reference, halves.rms / 2, out, "refined-end", exposure);

    // 3. The composed image of the drag (MATLAS_BENCH_NO_DRAG=1: skipped).
    if (std::getenv("MATLAS_BENCH_NO_DRAG") != nullptr) return 0;
    TraceSettings bs = base;
    bs.width = 256, bs.height = 192, bs.spp = 16;
    t0 = std::chrono::steady_clock::now();
    c0 = cpu_seconds();
    const GiBasis basis = build_gi_basis(model, *world, bs, {});
    std::printf("\nbasis 256x192, 16 spp, %d materials: %.0f s wall, %.0f s CPU\n", model.count() + 1, seconds_since(t0),
                cpu_seconds() - c0);
    TraceSettings small = bs;
    small.spp = ref_spp, small.seed = 779;
    const Image small_ref = trace(*world, bank.get(), small).full(0);
    const Image composed = basis.compose(w);
    const Errors ce = compare(composed, small_ref);
    std::printf("composed vs %d-spp reference: L1 %.4f, RMS %.4f, pixels > 20x the reference %d (+%d dark), largest ratio %.1f\n",
                ref_spp, ce.l1, ce.rms, ce.over20, ce.over20_dark, ce.max_ratio);
    // As served: the fireflies removed (render/firefly_filter.h, biased); MATLAS_BENCH_FIREFLY_RATIOS=a,b,...
    // tries other ratios than the served one (render::kFireflyRatio).
    std::vector<double> ratios = {render::kFireflyRatio};
    if (const char* list = std::getenv("MATLAS_BENCH_FIREFLY_RATIOS")) {
      ratios.clear();
      for (const char* p = list; *p;) {
        char* end = nullptr;
        ratios.push_back(std::strtod(p, &end));
        p = *end == ',' ? end + 1 : end;
      }
    }
    // MATLAS_BENCH_FIREFLY_RANKS=1,2: the neighbours' ranks compared with (the served one's alone by default).
    std::vector<int> ranks = {render::kFireflyRank};
    if (const char* list = std::getenv("MATLAS_BENCH_FIREFLY_RANKS")) {
      ranks.clear();
      for (const char* p = list; *p;) {
        char* end = nullptr;
        ranks.push_back(static_cast<int>(std::strtol(p, &end, 10)));
        p = *end == ',' ? end + 1 : end;
      }
    }
    for (const int rank : ranks)
    for (const double ratio : ratios) {
      Image filtered = composed;
      const int replaced = render::remove_fireflies(filtered, ratio, rank);
      const Errors fe = compare(filtered, small_ref);
      std::printf("composed and filtered at ratio %.1f, rank %d (%d pixels replaced): L1 %.4f, RMS %.4f, pixels > 20x %d "
                  "(+%d dark), largest ratio %.1f\n",
                  ratio, rank, replaced, fe.l1, fe.rms, fe.over20, fe.over20_dark, fe.max_ratio);
      if (ratio == render::kFireflyRatio && rank == render::kFireflyRank)
        write_png(out, "composed-filtered.png", filtered, exposure);
    }
    write_png(out, "composed.png", composed, exposure);
    std::printf("load average at the end %.1f\n", load_average());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
