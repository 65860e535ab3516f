// Accuracy of the rotated-ZH CPU reference (src/zonal) against the path tracer (src/render), the
// numbers of docs/REALTIME.md. Not a Google Benchmark: a study with its own main.
//
//   bench_zonal_accuracy [--env studio] [--bands 4,8,16,24,32] [--size 64] [--spp 4096]
//                        [--theta-o 32] [--rows 128] [--cols 256] [--texels 8] [--subsamples 2]
//                        [--chunk 12] [--dump DIR] FILE.binary... > results.csv
//
// For every material: two reference renders R1, R2 of a sphere with seeds 1 and 2 (the `matlas
// render` scene and camera; render_bank shares the samples of a chunk of materials, one bin index per sample), R = (R1 +
// R2) / 2, then for every L the coefficients, the prefiltered environment and shade_image Z.
// Errors: zonal/compare.h (l1 includes the reference's noise, rms is noise-free).
// Also prints per material its gloss
// ln(pi f_peak / A) (f_peak: luminance at theta_h bin 0, theta_d bin 10, phi_d bin 90; A: the
// luminance of the albedo at normal incidence) that classifies it. CSV on stdout, timings on stderr.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "brdf/albedo.h"
#include "core/error.h"
#include "formats/merl_file.h"
#include "render/material.h"
#include "render/render.h"
#include "zonal/compare.h"
#include "zonal/projection.h"
#include "zonal/shade.h"

namespace {

using namespace matlas;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// Tables on one grid evaluated together: one bin index per sample for all of them (the values
/// equal TableMaterial's lookups; render_bank's MaterialList would recompute the bin per table).
class TableBank final : public render::MaterialBank {
public:
  explicit TableBank(const std::vector<BrdfTable>& tables) : tables_(tables) {}
  int count() const override { return static_cast<int>(tables_.size()); }
  void eval_all(const Vec3& wi, const Vec3& wo, double* out) const override {
    const std::size_t bin = bin_of(tables_[0].dims(), wi, wo);
    for (std::size_t k = 0; k < tables_.size(); ++k) {
      const Rgb f = tables_[k].bin_rgb(bin);
      for (int c = 0; c < 3; ++c) out[3 * k + static_cast<std::size_t>(c)] = f[c];
    }
  }

private:
  const std::vector<BrdfTable>& tables_;
};

double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

double gloss(const BrdfTable& t) {
  const double peak = luminance(t.bin_rgb(t.dims().flat(0, 10, t.dims().phi_d / 2)));
  const double albedo = luminance(directional_albedo(t, 0.0));
  return std::log(std::max(kPi * peak, 1e-12) / std::max(albedo, 1e-12));
}

std::vector<int> parse_list(const std::string& s) {
  std::vector<int> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::stoi(item));
  return out;
}

int run(int argc, char** argv) {
  std::string env_name = "studio";
  std::vector<int> bands = {4, 8, 16, 24, 32};
  int size = 64, spp = 4096, theta_o = 32, rows = 128, cols = 256, subsamples = 2, chunk = 12;
  double texels = 8.0;
  std::vector<std::string> files;
  std::string dump;  // folder for PNGs of the references and shadings (inspection)
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--env") env_name = next();
    else if (a == "--bands") bands = parse_list(next());
    else if (a == "--size") size = std::stoi(next());
    else if (a == "--spp") spp = std::stoi(next());
    else if (a == "--theta-o") theta_o = std::stoi(next());
    else if (a == "--rows") rows = std::stoi(next());
    else if (a == "--cols") cols = std::stoi(next());
    else if (a == "--texels") texels = std::stod(next());
    else if (a == "--subsamples") subsamples = std::stoi(next());
    else if (a == "--chunk") chunk = std::stoi(next());
    else if (a == "--dump") dump = next();
    else files.push_back(a);
  }
  if (files.empty()) throw Error("no .binary files given");
  render::SceneDescription desc;  // the `matlas render` defaults: sphere, default camera
  desc.environment = env_name;
  const render::Scene scene(desc);
  render::RenderSettings rs;
  rs.width = rs.height = size;
  rs.spp = spp;
  const std::vector<float> coverage = render::object_coverage(scene, rs);
  zonal::ShadeSettings ss;
  ss.width = ss.height = size;
  ss.subsamples = subsamples;

  std::vector<std::unique_ptr<zonal::ZonalProjector>> projectors;
  std::vector<std::unique_ptr<zonal::PrefilteredEnvironment>> filtered;
  for (int L : bands) {
    zonal::ProjectionSettings ps{L, theta_o, rows, cols};
    auto t = std::chrono::steady_clock::now();
    projectors.push_back(std::make_unique<zonal::ZonalProjector>(ps));
    std::fprintf(stderr, "L=%d projector %.2f s", L, seconds_since(t));
    t = std::chrono::steady_clock::now();
    zonal::PrefilterSettings fs;
    fs.bands = L;
    fs.texels_per_band = texels;
    filtered.push_back(std::make_unique<zonal::PrefilteredEnvironment>(scene.environment(), fs));
    std::fprintf(stderr, ", prefilter %.2f s\n", seconds_since(t));
  }
  std::printf("material,gloss,L,l1,rms,noise\n");
  for (std::size_t begin = 0; begin < files.size(); begin += static_cast<std::size_t>(chunk)) {
    const std::size_t end = std::min(files.size(), begin + static_cast<std::size_t>(chunk));
    std::vector<BrdfTable> tables;
    for (std::size_t i = begin; i < end; ++i) tables.push_back(read_merl(files[i]));
    const TableBank bank(tables);
    auto t = std::chrono::steady_clock::now();
    const std::vector<Image> refs = render::render_bank(scene, bank, rs);
    render::RenderSettings other = rs;
    other.seed = 2;
    const std::vector<Image> refs2 = render::render_bank(scene, bank, other);
    std::fprintf(stderr, "reference of %zu materials (two seeds): %.1f s\n", tables.size(), seconds_since(t));
    for (std::size_t i = 0; i < tables.size(); ++i) {
      std::string name = files[begin + i];
      name = name.substr(name.find_last_of('/') + 1);
      const double g = gloss(tables[i]);
      for (std::size_t b = 0; b < bands.size(); ++b) {
        t = std::chrono::steady_clock::now();
        const zonal::ZonalCoefficients c = projectors[b]->project(tables[i]);
        const double tp = seconds_since(t);
        t = std::chrono::steady_clock::now();
        const Image img = zonal::shade_image(scene, projectors[b]->basis(), c, *filtered[b], ss);
        const zonal::ImageErrors e = zonal::compare_to_reference(img, refs[i], refs2[i], coverage);
        if (!dump.empty()) {
          const std::string stem = dump + "/" + name.substr(0, name.find('.'));
          if (b == 0) write_image(stem + "-ref.png", refs[i]);
          write_image(stem + "-L" + std::to_string(bands[b]) + ".png", img);
          Image diff = img;
          for (std::size_t v = 0; v < diff.rgb.size(); ++v)
            diff.rgb[v] = std::abs(img.rgb[v] - 0.5f * (refs[i].rgb[v] + refs2[i].rgb[v])) * 4.0f;
          write_image(stem + "-L" + std::to_string(bands[b]) + "-diff4.png", diff);
        }
        std::printf("%s,%.3f,%d,%.5f,%.5f,%.5f\n", name.c_str(), g, bands[b], e.l1, e.rms, e.noise);
        std::fprintf(stderr, "%s L=%d project %.3f s shade %.2f s\n", name.c_str(), bands[b], tp, seconds_since(t));
      }
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_zonal_accuracy: %s\n", e.what());
    return 1;
  }
}
