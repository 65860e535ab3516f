// Queries of a built model: export (a point as a MERL file; `eval` is its deprecated alias), latent,
// weights, project.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/print.h"
#include "cli/latent_point.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/merl_file.h"
#include "atlas/map_layers.h"
#include "manifold/export.h"
#include "formats/rgl_bsdf.h"
#include "formats/rgl_bsdf_writer.h"
#include "formats/rgl_export_check.h"
#include "manifold/project.h"

namespace matlas::cli {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

json vector_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

// ---- export
struct ExportArgs {
  std::string source, output, format;
  int theta_i = RglExportOptions{}.theta_i, rgb = RglExportOptions{}.rgb_resolution;
  int wavelengths = kSpectralExportWavelengths;  ///< bsdf-spectral
  int fit_iterations = RglSampleFitOptions{}.iterations;
  std::optional<std::string> at, material;
  bool check = true;
};

enum class ExportFormat { merl, bsdf, bsdf_spectral };

/// --format, or the output's extension (.bsdf) when --format is absent; a contradiction is refused.
ExportFormat export_format(const ExportArgs& a) {
  const bool bsdf_name = fs::path(a.output).extension() == ".bsdf";
  if (a.format.empty()) return bsdf_name ? ExportFormat::bsdf : ExportFormat::merl;
  if (a.format != "binary" && a.format != "bsdf" && a.format != "bsdf-spectral")
    throw Error("--format '" + a.format + "': expected binary (MERL), bsdf (RGL, RGB: Mitsuba 3) or bsdf-spectral "
                "(RGL, spectral: Mitsuba 3 and pbrt-v4)");
  const ExportFormat f = a.format == "bsdf"            ? ExportFormat::bsdf
                         : a.format == "bsdf-spectral" ? ExportFormat::bsdf_spectral
                                                       : ExportFormat::merl;
  if (f == ExportFormat::merl && bsdf_name)
    throw Error("-o " + a.output + ": a .bsdf name for --format binary (a MERL table); use --format bsdf or another name");
  return f;
}

void write_bsdf_export(const ExportArgs& a, ExportFormat format, const BrdfTable& table, const std::string& what,
                       const Io& io) {
  RglExportOptions options;
  options.theta_i = a.theta_i;
  options.rgb_resolution = a.rgb;
  options.fit.iterations = a.fit_iterations;
  options.description = "matlas export of " + what;
  if (format == ExportFormat::bsdf_spectral) options.wavelengths = a.wavelengths;
  RglExportReport report;
  write_rgl_bsdf(a.output, table, options, &report);
  const std::string kind = options.wavelengths > 0 ? "spectral, " + std::to_string(options.wavelengths) + " wavelengths 360-830 nm" : "RGB";
  print(io.out, "wrote %s (RGL .bsdf, isotropic %s, %d incident elevations, reflectance %dx%d, %.2f MB)\n",
        a.output.c_str(), kind.c_str(), options.theta_i, options.rgb_resolution, options.rgb_resolution,
        static_cast<double>(report.bytes) / 1e6);
  if (options.wavelengths > 0)
    print(io.out, "  spectra         sigmoid spectra (Jakob & Hanika 2019) reduce to the samples' RGB within %.3g %% RMS, "
          "%.3g %% at worst (relative to each sample's largest channel)\n",
          100 * report.spectral_error_rms, 100 * report.spectral_error_max);
  print(io.out, "  NDF             power iterations on the back-scattering: %d iterations, last change %.2g\n",
        report.ndf.iterations, report.ndf.last_change);
  if (report.fit.iterations > 0)
    print(io.out, "  samples         fitted to the table in least squares at %zu points (bin centres and the corners "
          "between them) and its albedo at %zu view angles; %d iterations: relative RMS at the points %.2f %% -> "
          "%.2f %%, %zu samples held at 0\n", report.fit.observations, report.fit.albedo_rows, report.fit.iterations,
          100 * report.fit.relative_rms_before, 100 * report.fit.relative_rms_after, report.fit.clipped);
  if (!a.check) return;
  const RglBsdf file = RglBsdf::read(a.output);
  const RglFidelity f = check_rgl_fidelity(file, table);
  print(io.out, "  fidelity        the file read back reproduces the table: cosine-weighted relative RMS %.2f %% over the "
        "bin centres, %.2f %% between them\n", 100 * f.relative_rms, 100 * f.relative_rms_between);
  for (std::size_t k = 0; k < f.angles_deg.size(); ++k) {
    const Rgb& t = f.table_albedo[k];
    const Rgb& b = f.file_albedo[k];
    print(io.out, "  albedo %2.0f deg   %.4f %.4f %.4f (table), %.4f %.4f %.4f (file); sampling variance %.3g "
          "(own) vs %.3g (cosine)\n", f.angles_deg[k], t[0], t[1], t[2], b[0], b[1], b[2], f.variance_own[k],
          f.variance_cosine[k]);
  }
  print(io.out, "  largest albedo difference %.2f %% (0-75 deg, per channel)\n", 100 * f.albedo_error);
  // The file interpolates linearly between elevations: a table whose reflection changes fast with
  // the angle of incidence (pearlescents) is closer with more of them (docs/EXPORT.md).
  if ((f.albedo_error > 0.01 || f.relative_rms > 0.02) && options.theta_i < 48)
    print(io.out, "  hint            above 1 %% in albedo or 2 %% RMS: more incident elevations (--theta-i 48, about "
          "%.1f MB) bring the file closer\n", static_cast<double>(report.bytes) / 1e6 * 48.0 / options.theta_i);
}

void run_export(const ExportArgs& a, const Io& io) {
  if (a.output.empty()) throw Error("-o: the output file name is empty");
  const ExportFormat format = export_format(a);
  refuse_output_among_inputs(a.output, {a.source});
  const fs::path source(a.source);
  BrdfTable table;
  std::string what;
  if (source.extension() == ".binary" || is_rgl_path(source)) {
    // A table file: converted as it is.
    if (a.at || a.material)
      throw Error(a.source + ": --at and --material pick a point of a model (.matlas), not of a table file");
    table = read_brdf(source);
    what = source.filename().string();
    if (format == ExportFormat::merl) {
      write_merl(a.output, table);
      print(io.out, "wrote %s (MERL table of %s)\n", a.output.c_str(), what.c_str());
      return;
    }
  } else {
    const Model model = Model::open(a.source);
    const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
    const Eigen::VectorXd w = a.material ? model.material_weights(model.index_of(*a.material)) : model.weights(x);
    const double variance = model.variance(x);
    // Far from the data the map's BRDF is an extrapolation: exported, but said loudly.
    if (!a.material && variance >= atlas::kFadeFrom)
      print(io.err, "warning: x = %s is far from the data (predictive variance %.3g, maps fade out from %.2g): the "
            "exported BRDF is an extrapolation, not a measured material\n", point_text(x).c_str(), variance, atlas::kFadeFrom);
    ExportStats stats;
    table = export_table(model, w, &stats);
    what = a.material ? "material " + *a.material + " of " + source.filename().string()
                      : "x = " + point_text(x) + " of " + source.filename().string();
    if (format == ExportFormat::merl) write_merl(a.output, table);
    else write_bsdf_export(a, format, table, what, io);
    if (format == ExportFormat::merl)
      print(io.out, "wrote %s (x = %s, predictive variance %.3g)\n", a.output.c_str(), point_text(x).c_str(), variance);
    else
      print(io.out, "  point           x = %s, predictive variance %.3g\n", point_text(x).c_str(), variance);
    if (stats.clamped)
      print(io.out, "  clamped %zu negative values to 0 (most negative %.3g)\n", stats.clamped, stats.most_negative);
    if (stats.missing) print(io.out, "  %zu values written as missing (-1): not measured in every input\n", stats.missing);
    return;
  }
  write_bsdf_export(a, format, table, what, io);
}

// ---- latent
void run_latent(const std::string& path, bool as_json, const Io& io) {
  const Model model = Model::open(path);
  if (as_json) {
    json j = {{"q", model.dim()}, {"materials", json::array()}};
    for (int i = 0; i < model.count(); ++i)
      j["materials"].push_back({{"name", model.names()[static_cast<std::size_t>(i)]},
                                {"x", vector_json(model.latent().row(i).transpose())}});
    print(io.out, "%s\n", j.dump(2).c_str());
    return;
  }
  for (int i = 0; i < model.count(); ++i) {
    print(io.out, "%-32s", model.names()[static_cast<std::size_t>(i)].c_str());
    for (int k = 0; k < model.dim(); ++k) print(io.out, " %10.5f", model.latent()(i, k));
    print(io.out, "\n");
  }
}

// ---- weights
struct WeightsArgs {
  std::string model;
  std::optional<std::string> at, material;
  bool json = false;
  int top = 10;
};

void run_weights(const WeightsArgs& a, const Io& io) {
  const Model model = Model::open(a.model);
  const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
  const Eigen::VectorXd w = model.weights(x);
  const double variance = model.variance(x);
  if (a.json) {
    json j = {{"x", vector_json(x)}, {"variance", variance}, {"weights", json::array()},
              {"sum", w.sum()}};
    for (int i = 0; i < model.count(); ++i)
      j["weights"].push_back({{"name", model.names()[static_cast<std::size_t>(i)]}, {"w", w[i]}});
    print(io.out, "%s\n", j.dump(2).c_str());
    return;
  }
  print(io.out, "x = %s\npredictive variance %.6g (0 at the data, ~1 far from it)\nsum of weights %.6f\n",
              point_text(x).c_str(), variance, w.sum());
  std::vector<int> order(static_cast<std::size_t>(model.count()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) { return std::abs(w[i]) > std::abs(w[j]); });
  const int shown = std::min(a.top, model.count());
  print(io.out, "largest %d weights:\n", shown);
  for (int k = 0; k < shown; ++k) {
    const int i = order[static_cast<std::size_t>(k)];
    print(io.out, "  %+10.6f  %s\n", w[i], model.names()[static_cast<std::size_t>(i)].c_str());
  }
}

// ---- project
void run_project(const std::string& model_path, const std::string& file, bool as_json, const Io& io) {
  const Model model = Model::open(model_path);
  const BrdfTable table = read_brdf(file);  // .bsdf: resampled onto the MERL grid
  Projection p;
  try {
    p = project_material(model, table);
  } catch (const Error& e) {
    throw file_error(file, e.what());
  }
  const std::string nearest = model.names()[static_cast<std::size_t>(p.nearest)];
  if (as_json) {
    json j = {{"file", file}, {"x", vector_json(p.x)}, {"relative_error", p.relative_error},
              {"variance", p.variance}, {"nearest", nearest},
              {"nearest_relative_error", p.nearest_relative_error}, {"missing_columns", p.missing}};
    print(io.out, "%s\n", j.dump(2).c_str());
    return;
  }
  print(io.out, "%s\n  latent point      %s\n  residual          %.4g (relative L2 over %zu kept columns)\n"
              "  variance          %.4g\n  nearest material  %s (relative L2 %.4g)\n",
              file.c_str(), point_text(p.x).c_str(), p.relative_error, model.kept_columns(), p.variance,
              nearest.c_str(), p.nearest_relative_error);
  if (p.missing) print(io.out, "  note: %zu kept columns are not measured in this file and were skipped\n", p.missing);
}

void add_query_commands(CLI::App& app, const Io& io) {
  {
    auto a = std::make_shared<ExportArgs>();
    auto* cmd = app.add_subcommand(
        "export", "Export the BRDF at a latent point, a model's material or a table file as a MERL .binary or an "
                  "RGL .bsdf file (Mitsuba 3, pbrt-v4; docs/EXPORT.md) (alias: eval, deprecated)");
    cmd->alias("eval");  // the command's old name, kept for scripts written before the rename
    cmd->add_option("source", a->source, "Model file (.matlas), or a table file (.binary, .bsdf) to convert")
        ->required();
    add_point_options(*cmd, a->at, a->material);
    cmd->add_option("-o,--output", a->output, "Output file (.binary, or .bsdf)")->required();
    cmd->add_option("--format", a->format,
                    "binary (MERL, the default), bsdf (RGL tensor file, RGB: Mitsuba 3) or bsdf-spectral (RGL, "
                    "spectral: Mitsuba 3 and pbrt-v4); default from the output's extension (.bsdf: RGB)");
    cmd->add_option("--wavelengths", a->wavelengths, "bsdf-spectral: wavelengths, evenly over 360-830 nm")
        ->check(CLI::Range(3, 200))
        ->capture_default_str();
    cmd->add_option("--theta-i", a->theta_i, "bsdf: incident elevations")->check(CLI::Range(2, 90))->capture_default_str();
    cmd->add_option("--rgb-resolution", a->rgb, "bsdf: reflectance samples per axis per elevation")
        ->check(CLI::Range(2, 256))
        ->capture_default_str();
    cmd->add_option("--fit-iterations", a->fit_iterations,
                    "bsdf: least-squares iterations fitting the samples to the table (its bin centres, the corners "
                    "between them, its albedo; 0: the table's values at the sample points)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    cmd->add_flag("!--no-check", a->check, "bsdf: skip reading the file back and measuring its fidelity (faster)");
    cmd->callback([io, a] { run_export(*a, io); });
  }
  {
    auto path = std::make_shared<std::string>();
    auto as_json = std::make_shared<bool>(false);
    auto* cmd = app.add_subcommand("latent", "List the materials and their latent coordinates");
    cmd->add_option("model", *path, "Model file (.matlas)")->required();
    cmd->add_flag("--json", *as_json, "JSON output");
    cmd->callback([io, path, as_json] { run_latent(*path, *as_json, io); });
  }
  {
    auto a = std::make_shared<WeightsArgs>();
    auto* cmd = app.add_subcommand("weights", "Interpolation weights w(x) and predictive variance at a point");
    cmd->add_option("model", a->model, "Model file (.matlas)")->required();
    add_point_options(*cmd, a->at, a->material);
    cmd->add_flag("--json", a->json, "JSON output with every weight");
    cmd->add_option("--top", a->top, "How many of the largest weights to list")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->callback([io, a] { run_weights(*a, io); });
  }
  {
    auto model = std::make_shared<std::string>();
    auto file = std::make_shared<std::string>();
    auto as_json = std::make_shared<bool>(false);
    auto* cmd = app.add_subcommand("project", "Find where a measured material falls on the map");
    cmd->add_option("model", *model, "Model file (.matlas)")->required();
    cmd->add_option("file", *file, "MERL .binary or RGL .bsdf file")->required();
    cmd->add_flag("--json", *as_json, "JSON output");
    cmd->callback([io, model, file, as_json] { run_project(*model, *file, *as_json, io); });
  }
}

}  // namespace

MATLAS_COMMAND(40, add_query_commands);

}  // namespace matlas::cli
