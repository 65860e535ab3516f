// Accuracy of the rotated-ZH CPU reference (src/zonal) against the path tracer (src/render), the
// numbers of docs/REALTIME.md. Not a Google Benchmark: a study with its own main.
//
//   bench_zonal_accuracy [--env studio[,forest,...|all]] [--bands 4,8,16,24,32] [--size 64]
//                        [--spp 4096] [--theta-o 32] [--rows 128] [--cols 256] [--texels 8]
//                        [--subsamples 2] [--chunk 12] [--window none[,hann,...]]
//                        [--lobes none|64,256,...] [--lights K[:RATIO[:MERGE]]]
//                        [--ref-cache DIR] [--dump DIR] FILE.binary... > results.csv
//   bench_zonal_accuracy --sheet OUT.png [--env studio] [--sheet-size 128] [--sheet-spp 1024]
//                        [--bands 16] [--lobes ...] [--window ...] [--texels 8] [--exposure 0]
//                        FILE.binary...
//
// --sheet: a comparison picture instead of the study: one row per material, columns the path
// tracer (render_bank, one seed), then the shading with --lobes and each of --window's entries;
// 4 x 4 rays per pixel, the environment behind the sphere, clamp tone map at `exposure` stops.
//
// --lobes: the sharp lobes fitted beside the expansion (zonal/lobes.h; default none, "default":
// zonal::kDefaultLobes). --env all: every installed environment. --window: the windows to shade
// with, one row per entry: a band window (zonal/window.h), or ring:F, the coefficients weighted
// per theta_o sample by zonal::RingLimiter with floor F (zonal/ring_limit.h) and shaded without
// a window (the viewer: ring:0.05); any entry with the suffix "+lights" (the viewer:
// ring:0.05+lights) also moves the environment's brightest texels out of its maps and shades them
// as direct lights with each material's light table (zonal/light_split.h, zonal/light_table.h;
// --lights: at most K texels or blocks, RATIO times the mean luminance, MERGE texels per block
// side; default the viewer's 512:8:1); the CSV's lights column
// says K or 0. Each material's t per view angle is printed on stderr. --ref-cache: the reference renders are read from (or
// written to) DIR as raw float32 files named by environment, size, spp, seed and material, so
// that a second study of the same scene only shades.
//
// For every material: two reference renders R1, R2 of a sphere with seeds 1 and 2 (the `matlas
// render` scene and camera; render_bank shares the samples of a chunk of materials, one bin index per sample), R = (R1 +
// R2) / 2, then for every L the coefficients, the prefiltered environment and shade_image Z.
// Errors: zonal/compare.h (l1 includes the reference's noise, rms is noise-free).
// Also prints per material its gloss
// ln(pi f_peak / A) (f_peak: luminance at theta_h bin 0, theta_d bin 10, phi_d bin 90; A: the
// luminance of the albedo at normal incidence) that classifies it. CSV on stdout, timings on stderr.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "brdf/albedo.h"
#include "core/error.h"
#include "formats/merl_file.h"
#include "render/assets.h"
#include "render/material.h"
#include "render/render.h"
#include "zonal/compare.h"
#include "zonal/light_split.h"
#include "zonal/light_table.h"
#include "zonal/projection.h"
#include "zonal/ring_limit.h"
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

std::vector<std::string> split_list(const std::string& s, char sep = ':') {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, sep)) out.push_back(item);
  return out;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

std::vector<int> parse_list(const std::string& s) {
  std::vector<int> out;
  for (const std::string& item : split(s)) out.push_back(std::stoi(item));
  return out;
}

std::string stem_of(const std::string& file) {
  std::string name = file.substr(file.find_last_of('/') + 1);
  return name.substr(0, name.find('.'));
}

/// A cached reference image (raw float32 RGB, width * height * 3), or false.
bool read_cached(const std::string& path, int size, Image* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  Image img(size, size);
  in.read(reinterpret_cast<char*>(img.rgb.data()), static_cast<std::streamsize>(img.rgb.size() * sizeof(float)));
  if (!in || in.peek() != EOF) return false;
  *out = std::move(img);
  return true;
}

void write_cached(const std::string& path, const Image& img) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(reinterpret_cast<const char*>(img.rgb.data()), static_cast<std::streamsize>(img.rgb.size() * sizeof(float)));
    if (!out) throw Error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

/// A window to shade with: a band window (zonal/window.h), or "ring:F", the coefficients after
/// zonal::RingLimiter with floor F and no window (the per-sample window of zonal/ring_limit.h).
struct WindowChoice {
  zonal::BandWindow window = zonal::BandWindow::none;
  double ring_floor = -1.0;  ///< < 0: no ring limit
  std::string name;          ///< without the "+lights" suffix
  bool lights = false;       ///< the environment's brightest texels as direct lights (--lights)
};

WindowChoice parse_window_choice(std::string w) {
  const std::string suffix = "+lights";
  const bool lights = w.size() > suffix.size() && w.compare(w.size() - suffix.size(), suffix.size(), suffix) == 0;
  if (lights) w.resize(w.size() - suffix.size());
  if (w.rfind("ring:", 0) == 0) return {zonal::BandWindow::none, std::stod(w.substr(5)), w, lights};
  return {zonal::parse_band_window(w), -1.0, w, lights};
}

/// Every material's coefficients as shaded with `choice`: as projected, or ring-limited by one
/// limiter for all of them (each material's t per view angle on stderr, under `names`).
std::vector<zonal::ZonalCoefficients> shaded_coefficients(const zonal::ZonalBasis& basis,
                                                          const std::vector<zonal::ZonalCoefficients>& projected,
                                                          const std::vector<std::string>& names,
                                                          const WindowChoice& choice) {
  std::vector<zonal::ZonalCoefficients> out = projected;
  if (choice.ring_floor < 0.0 || out.empty()) return out;
  zonal::RingLimit limit;
  limit.floor = choice.ring_floor;
  const zonal::RingLimiter limiter(basis, out.front(), limit);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::vector<double> ts = limiter.apply(out[i]);
    std::fprintf(stderr, "%s L=%d %s t:", names[i].c_str(), out[i].bands, choice.name.c_str());
    for (double v : ts) std::fprintf(stderr, " %.2f", v);
    std::fprintf(stderr, "\n");
  }
  return out;
}

/// The comparison sheet (see the top of the file).
void write_sheet(const std::string& out, const std::string& env_name, const std::vector<std::string>& files, int L,
                 int theta_o, int size, int spp, double exposure, const std::vector<WindowChoice>& choices,
                 const std::vector<double>& lobes, double texels, const zonal::LightSplitSettings& light_settings) {
  render::SceneDescription desc;
  desc.environment = env_name;
  const render::Scene scene(desc);
  render::RenderSettings rs;
  rs.width = rs.height = size;
  rs.spp = spp;
  std::vector<BrdfTable> tables;
  for (const std::string& f : files) tables.push_back(read_merl(f));
  const TableBank bank(tables);
  const std::vector<Image> refs = render::render_bank(scene, bank, rs);
  const int gap = 4, cols = 1 + static_cast<int>(choices.size()), rows = static_cast<int>(files.size());
  Image sheet(cols * size + (cols - 1) * gap, rows * size + (rows - 1) * gap);
  std::fill(sheet.rgb.begin(), sheet.rgb.end(), 1.0f);
  auto place = [&](const Image& img, int row, int col) {
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float* p = img.pixel(x, y);
        float* q = sheet.pixel(col * (size + gap) + x, row * (size + gap) + y);
        for (int c = 0; c < 3; ++c) q[c] = p[c];
      }
  };
  zonal::ShadeSettings ss;
  ss.width = ss.height = size;
  ss.subsamples = 4;
  const zonal::ProjectionSettings ps{L, theta_o, 128, 256, lobes};
  const zonal::ZonalProjector projector(ps);
  zonal::PrefilterSettings fs;
  fs.bands = L;
  fs.lobes = ps.lobes;
  fs.texels_per_band = texels;
  const zonal::PrefilteredEnvironment env(scene.environment(), fs);
  const zonal::LightSplit split = zonal::split_lights(scene.environment(), light_settings);
  const zonal::PrefilteredEnvironment residual(split.residual, fs);
  std::vector<zonal::ZonalCoefficients> projected;
  std::vector<zonal::LightTable> light_tables;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    place(refs[i], static_cast<int>(i), 0);
    projected.push_back(projector.project(tables[i]));
    light_tables.push_back(zonal::LightTable::reduce(tables[i]));
    names.push_back(files[i]);
  }
  for (std::size_t v = 0; v < choices.size(); ++v) {
    ss.window = choices[v].window;
    const std::vector<zonal::ZonalCoefficients> shaded = shaded_coefficients(projector.basis(), projected, names, choices[v]);
    for (std::size_t i = 0; i < tables.size(); ++i) {
      const zonal::LightTableMaterial material(light_tables[i]);
      const zonal::DirectLights direct{&split.points, &material};
      place(choices[v].lights ? zonal::shade_image(scene, projector.basis(), shaded[i], residual, ss, &direct)
                              : zonal::shade_image(scene, projector.basis(), shaded[i], env, ss),
            static_cast<int>(i), 1 + static_cast<int>(v));
    }
  }
  ToneMap tone;
  tone.exposure = exposure;
  write_image(out, sheet, tone);
}

int run(int argc, char** argv) {
  std::string env_names = "studio", windows = "none", ref_cache;
  std::vector<double> lobes;
  std::vector<int> bands = {4, 8, 16, 24, 32};
  int size = 64, spp = 4096, theta_o = 32, rows = 128, cols = 256, subsamples = 2, chunk = 12;
  double texels = 8.0;
  std::vector<std::string> files;
  std::string dump;  // folder for PNGs of the references and shadings (inspection)
  std::string sheet;
  int sheet_size = 128, sheet_spp = 1024;
  double exposure = 0.0;
  zonal::LightSplitSettings light_settings{512, 8.0, 1};  // the viewer's (server/realtime.h)
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--env") env_names = next();
    else if (a == "--window") windows = next();
    else if (a == "--ref-cache") ref_cache = next();
    else if (a == "--lobes") {
      const std::string v = next();
      lobes.clear();
      if (v == "default") lobes = zonal::kDefaultLobes;
      else if (v != "none")
        for (const std::string& item : split(v)) lobes.push_back(std::stod(item));
    }
    else if (a == "--lights") {  // K[:ratio[:merge]]
      const std::vector<std::string> v = split_list(next());
      light_settings.max_texels = std::stoi(v.at(0));
      if (v.size() > 1) light_settings.ratio = std::stod(v[1]);
      if (v.size() > 2) light_settings.merge = std::stoi(v[2]);
    }
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
    else if (a == "--sheet") sheet = next();
    else if (a == "--sheet-size") sheet_size = std::stoi(next());
    else if (a == "--sheet-spp") sheet_spp = std::stoi(next());
    else if (a == "--exposure") exposure = std::stod(next());
    else files.push_back(a);
  }
  if (files.empty()) throw Error("no .binary files given");
  if (!sheet.empty()) {
    std::vector<WindowChoice> choices;
    for (const std::string& w : split(windows)) choices.push_back(parse_window_choice(w));
    write_sheet(sheet, env_names, files, bands.front(), theta_o, sheet_size, sheet_spp, exposure, choices, lobes,
                texels, light_settings);
    return 0;
  }
  std::vector<std::string> envs = split(env_names);
  if (env_names == "all") envs = installed_environments();
  std::vector<WindowChoice> window_list;
  for (const std::string& w : split(windows)) window_list.push_back(parse_window_choice(w));
  render::RenderSettings rs;
  rs.width = rs.height = size;
  rs.spp = spp;

  // Coefficients of every material at every L: computed once, shaded under every environment.
  std::vector<BrdfTable> all_tables;
  std::vector<std::string> names;
  std::vector<double> glosses;
  for (const std::string& f : files) {
    all_tables.push_back(read_merl(f));
    names.push_back(stem_of(f));
    glosses.push_back(gloss(all_tables.back()));
  }
  bool with_lights = false, without_lights = false;  // some windows shade the lights, some do not
  for (const WindowChoice& choice : window_list) (choice.lights ? with_lights : without_lights) = true;
  std::vector<zonal::LightTable> light_tables;  // what the direct lights read (zonal/light_table.h)
  if (with_lights)
    for (const BrdfTable& table : all_tables) light_tables.push_back(zonal::LightTable::reduce(table));
  std::vector<std::unique_ptr<zonal::ZonalProjector>> projectors;
  std::vector<std::vector<zonal::ZonalCoefficients>> coefficients;  // [L][material]
  for (int L : bands) {
    zonal::ProjectionSettings ps{L, theta_o, rows, cols, lobes};
    auto t = std::chrono::steady_clock::now();
    projectors.push_back(std::make_unique<zonal::ZonalProjector>(ps));
    coefficients.emplace_back();
    for (const BrdfTable& table : all_tables) coefficients.back().push_back(projectors.back()->project(table));
    std::fprintf(stderr, "L=%d projector and %zu projections %.2f s\n", L, files.size(), seconds_since(t));
  }
  // Per L and window, the coefficients as shaded (ring limits applied once, not per environment).
  std::vector<std::vector<std::vector<zonal::ZonalCoefficients>>> shaded(bands.size());  // [L][window][material]
  for (std::size_t b = 0; b < bands.size(); ++b)
    for (const WindowChoice& choice : window_list)
      shaded[b].push_back(shaded_coefficients(projectors[b]->basis(), coefficients[b], names, choice));
  if (!ref_cache.empty()) std::filesystem::create_directories(ref_cache);
  std::printf("environment,material,gloss,L,lobes,window,lights,l1,rms,noise\n");
  for (const std::string& env_name : envs) {
    render::SceneDescription desc;  // the `matlas render` defaults: sphere, default camera
    desc.environment = env_name;
    const render::Scene scene(desc);
    const std::vector<float> coverage = render::object_coverage(scene, rs);
    std::vector<std::unique_ptr<zonal::PrefilteredEnvironment>> filtered, filtered_residual;
    zonal::LightSplit lights{scene.environment(), {}, 0, 0.0};
    if (with_lights) {
      lights = zonal::split_lights(scene.environment(), light_settings);
      std::fprintf(stderr, "%s: %d light texels (%zu points), %.1f %% of the map's luminance\n", env_name.c_str(),
                   lights.texels, lights.points.size(), 100.0 * lights.light_fraction);
    }
    for (int L : bands) {
      auto t = std::chrono::steady_clock::now();
      zonal::PrefilterSettings fs;
      fs.bands = L;
      fs.texels_per_band = texels;
      fs.lobes = lobes;
      if (without_lights) filtered.push_back(std::make_unique<zonal::PrefilteredEnvironment>(scene.environment(), fs));
      if (with_lights) filtered_residual.push_back(std::make_unique<zonal::PrefilteredEnvironment>(lights.residual, fs));
      std::fprintf(stderr, "%s L=%d prefilter %.2f s\n", env_name.c_str(), L, seconds_since(t));
    }
    // References: from the cache, else rendered a chunk at a time (render_bank shares samples).
    std::vector<Image> refs(files.size()), refs2(files.size());
    auto cached = [&](std::size_t i, int seed) {
      return ref_cache + "/" + env_name + "-" + std::to_string(size) + "-" + std::to_string(spp) + "-s" +
             std::to_string(seed) + "-" + names[i] + ".f32";
    };
    std::vector<std::size_t> missing;
    for (std::size_t i = 0; i < files.size(); ++i)
      if (ref_cache.empty() || !read_cached(cached(i, 1), size, &refs[i]) || !read_cached(cached(i, 2), size, &refs2[i]))
        missing.push_back(i);
    for (std::size_t begin = 0; begin < missing.size(); begin += static_cast<std::size_t>(chunk)) {
      const std::size_t end = std::min(missing.size(), begin + static_cast<std::size_t>(chunk));
      std::vector<BrdfTable> tables;
      for (std::size_t k = begin; k < end; ++k) tables.push_back(all_tables[missing[k]]);
      const TableBank bank(tables);
      auto t = std::chrono::steady_clock::now();
      const std::vector<Image> r1 = render::render_bank(scene, bank, rs);
      render::RenderSettings other = rs;
      other.seed = 2;
      const std::vector<Image> r2 = render::render_bank(scene, bank, other);
      for (std::size_t k = begin; k < end; ++k) {
        refs[missing[k]] = r1[k - begin];
        refs2[missing[k]] = r2[k - begin];
        if (!ref_cache.empty()) {
          write_cached(cached(missing[k], 1), r1[k - begin]);
          write_cached(cached(missing[k], 2), r2[k - begin]);
        }
      }
      std::fprintf(stderr, "%s: reference of %zu materials (two seeds): %.1f s\n", env_name.c_str(), tables.size(),
                   seconds_since(t));
    }
    for (std::size_t i = 0; i < files.size(); ++i) {
      for (std::size_t b = 0; b < bands.size(); ++b)
        for (std::size_t c = 0; c < window_list.size(); ++c) {
          const WindowChoice& choice = window_list[c];
          auto t = std::chrono::steady_clock::now();
          zonal::ShadeSettings ss;
          ss.width = ss.height = size;
          ss.subsamples = subsamples;
          ss.window = choice.window;
          std::optional<zonal::LightTableMaterial> material;
          if (choice.lights) material.emplace(light_tables[i]);
          const zonal::DirectLights direct{&lights.points, material ? &*material : nullptr};
          const Image img = choice.lights ? zonal::shade_image(scene, projectors[b]->basis(), shaded[b][c][i],
                                                               *filtered_residual[b], ss, &direct)
                                          : zonal::shade_image(scene, projectors[b]->basis(), shaded[b][c][i], *filtered[b], ss);
          const zonal::ImageErrors e = zonal::compare_to_reference(img, refs[i], refs2[i], coverage);
          const char* wname = choice.name.c_str();
          if (!dump.empty()) {
            std::filesystem::create_directories(dump);
            const std::string stem = dump + "/" + env_name + "-" + names[i];
            if (b == 0) write_image(stem + "-ref.png", refs[i]);
            const std::string tag = "-L" + std::to_string(bands[b]) + "-" + wname;
            write_image(stem + tag + ".png", img);
            Image diff = img;
            for (std::size_t v = 0; v < diff.rgb.size(); ++v)
              diff.rgb[v] = std::abs(img.rgb[v] - 0.5f * (refs[i].rgb[v] + refs2[i].rgb[v])) * 4.0f;
            write_image(stem + tag + "-diff4.png", diff);
          }
          std::printf("%s,%s,%.3f,%d,%zu,%s,%d,%.5f,%.5f,%.5f\n", env_name.c_str(), names[i].c_str(), glosses[i],
                      bands[b], lobes.size(), wname, choice.lights ? light_settings.max_texels : 0, e.l1, e.rms, e.noise);
          std::fprintf(stderr, "%s %s L=%d %s shade %.2f s\n", env_name.c_str(), names[i].c_str(), bands[b], wname,
                       seconds_since(t));
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
