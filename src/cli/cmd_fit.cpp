// matlas fit: the glTF metallic-roughness parameters (brdf/gltf_pbr.h), or those of Blender
// 2.8-3.6's Principled BSDF (brdf/principled_v1.h), that come closest to a map
// point, a model's material or a table file, written for artists' tools (glTF, MaterialX, Blender), with the
// fit's error (docs/EXPORT.md, "Analytic fits").
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "artist/blender_snippet.h"
#include "artist/fit_error.h"
#include "artist/fit_report.h"
#include "artist/gltf_material.h"
#include "artist/materialx_document.h"
#include "artist/pbr_fit.h"
#include "atlas/map_layers.h"
#include "brdf/tabulate.h"
#include "cli/commands.h"
#include "cli/latent_point.h"
#include "cli/print.h"
#include "core/atomic_file.h"
#include "core/check.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"
#include "manifold/export.h"

namespace matlas::cli {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct ArtistFitArgs {
  std::string source, name, model = "gltf";
  std::vector<std::string> outputs;
  std::optional<std::string> at, material;
};

enum class FitOutput { gltf, materialx, blender, report, table };

FitOutput output_kind(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".gltf") return FitOutput::gltf;
  if (ext == ".mtlx") return FitOutput::materialx;
  if (ext == ".py") return FitOutput::blender;
  if (ext == ".json") return FitOutput::report;
  if (ext == ".binary") return FitOutput::table;
  throw Error("-o " + path + ": unknown output type '" + ext +
              "'; expected .gltf (glTF 2.0 material), .mtlx (MaterialX 1.39, OpenPBR Surface), .py (Blender script), .json (fit report) or .binary "
              "(the fit tabulated as a MERL table)");
}

/// The fitted parameters, as the model names them.
void print_parameters(const GltfPbr& m, const std::string& what, const Io& io) {
  print(io.out, "fit of %s: glTF metallic-roughness\n", what.c_str());
  print(io.out, "  base colour     %.4f %.4f %.4f\n  metallic        %.4f\n  roughness       %.4f (alpha %.4g)\n"
        "  specular        %.4f (KHR_materials_specular, IOR %.2f)\n  clearcoat       %.4f, roughness %.4f\n"
        "  sheen           %.4f %.4f %.4f, roughness %.4f (KHR_materials_sheen)\n",
        m.base_color[0], m.base_color[1], m.base_color[2], m.metallic, m.roughness, m.alpha(), m.specular, m.ior,
        m.clearcoat, m.clearcoat_roughness, m.sheen_color[0], m.sheen_color[1], m.sheen_color[2], m.sheen_roughness);
}

void print_parameters(const PrincipledV1& m, const std::string& what, const Io& io) {
  print(io.out, "fit of %s: Blender 2.8-3.6 Principled BSDF (GGX)\n", what.c_str());
  print(io.out, "  base colour     %.4f %.4f %.4f\n  metallic        %.4f\n  specular        %.4f (tint %.2f)\n"
        "  roughness       %.4f\n  sheen           %.4f (tint %.2f)\n  coat layer      %.4f, roughness %.4f\n",
        m.base_color[0], m.base_color[1], m.base_color[2], m.metallic, m.specular, m.specular_tint, m.roughness, m.sheen,
        m.sheen_tint, m.coat, m.coat_roughness);
}

/// What the source is and how it is named in the files.
struct FitSource {
  BrdfTable table;
  std::string what, name;
  std::optional<double> variance;  ///< a map point's predictive variance
};

/// Fits the model (`fitter`: artist::fit_gltf_pbr or fit_principled_v1), prints it, its error and
/// the search, and writes the outputs (run_fit has refused those the model has not).
template <class Fitted>
void fit_and_write(artist::AnalyticFit<Fitted> (*fitter)(const BrdfTable&, const artist::PbrFitOptions&),
                   const ArtistFitArgs& a, const std::vector<FitOutput>& kinds, const FitSource& src, const Io& io) {
  const auto start = std::chrono::steady_clock::now();
  const artist::AnalyticFit<Fitted> fit = fitter(src.table, {});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const artist::FitError error = artist::fit_error(src.table, fit.model);
  print_parameters(fit.model, src.what, io);
  print(io.out, "  relative RMS    %.2f %% (cosine-weighted, against the table)\n", 100 * error.relative_rms);
  print(io.out, "  cube-root dist. %.4g\n  albedo          largest difference %.2f %% (0-75 deg, per channel)\n",
        error.cbrt_distance, 100 * error.albedo_error);
  print(io.out, "  search          %d starts, %d evaluations on %zu bins, objective %.4g, %.1f s\n", fit.starts,
        fit.evaluations, fit.samples, fit.distance, seconds);
  if (!fit.converged())
    print(io.err, "warning: the fit did not converge: a restart still lowered its objective (the cube-root "
          "distance integrated over direction pairs) by %.3g to %.4g; the parameters may be a little off\n", fit.restart_gain, fit.distance);
  for (std::size_t k = 0; k < a.outputs.size(); ++k) {
    const std::string& out = a.outputs[k];
    switch (kinds[k]) {
      case FitOutput::gltf:
      case FitOutput::materialx:
        if constexpr (std::is_same_v<Fitted, GltfPbr>) {
          if (kinds[k] == FitOutput::gltf) artist::write_gltf_material(out, fit.model, src.name, src.what);
          else artist::write_materialx_document(out, fit.model, src.name, src.what);
        } else {
          MATLAS_CHECK(false, "a glTF or MaterialX output of another model is refused in run_fit");
        }
        break;
      case FitOutput::blender: artist::write_blender_snippet(out, fit.model, src.name, src.what); break;
      case FitOutput::table: write_merl(out, tabulate(fit.model)); break;
      case FitOutput::report: {
        AtomicFile file(out);
        file.write(artist::fit_report_json(src.what, fit, error, seconds, src.variance)
                       .dump(2, ' ', false, json::error_handler_t::replace) + "\n");
        file.commit();
        break;
      }
    }
    print(io.out, "wrote %s\n", out.c_str());
  }
}

/// The table to fit: a table file as it is, or a model's material or point tabulated (a point far
/// from the data with a warning).
FitSource fit_source(const ArtistFitArgs& a, const Io& io) {
  const fs::path source(a.source);
  FitSource src;
  src.name = a.name;
  if (source.extension() == ".binary" || is_rgl_path(source)) {
    if (a.at || a.material)
      throw Error(a.source + ": --at and --material pick a point of a model (.matlas), not of a table file");
    src.table = read_brdf(source);
    src.what = source.filename().string();
    if (src.name.empty()) src.name = source.stem().string();
    return src;
  }
  const Model model = Model::open(a.source);
  const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
  const Eigen::VectorXd w = a.material ? model.material_weights(model.index_of(*a.material)) : model.weights(x);
  src.variance = model.variance(x);
  if (!a.material && *src.variance >= atlas::kFadeFrom)
    print(io.err, "warning: x = %s is far from the data (predictive variance %.3g, maps fade out from %.2g): the "
          "fitted BRDF is an extrapolation, not a measured material\n", point_text(x).c_str(), *src.variance, atlas::kFadeFrom);
  src.table = export_table(model, w);
  src.what = a.material ? "material " + *a.material + " of " + source.filename().string()
                        : "x = " + point_text(x) + " of " + source.filename().string();
  if (src.name.empty()) src.name = a.material ? *a.material : "matlas point " + point_text(x);
  return src;
}

void run_fit(const ArtistFitArgs& a, const Io& io) {
  if (a.outputs.empty()) throw Error("-o: give at least one output (.gltf, .mtlx, .py, .json or .binary)");
  std::vector<FitOutput> kinds;
  for (const std::string& o : a.outputs) {
    if (o.empty()) throw Error("-o: an output file name is empty");
    kinds.push_back(output_kind(o));
    if (a.model == "principled-v1" && (kinds.back() == FitOutput::gltf || kinds.back() == FitOutput::materialx))
      throw Error("-o " + o + ": --model principled-v1 fits Blender 2.8-3.6's Principled BSDF, which glTF and "
                  "MaterialX (OpenPBR Surface) do not have; fit with --model gltf (the default) for .gltf and .mtlx");
    refuse_output_among_inputs(o, {a.source});
  }
  const FitSource src = fit_source(a, io);

  if (a.model == "principled-v1")
    fit_and_write(&artist::fit_principled_v1, a, kinds, src, io);
  else
    fit_and_write(&artist::fit_gltf_pbr, a, kinds, src, io);
}

void add_fit_command(CLI::App& app, const Io& io) {
  auto a = std::make_shared<ArtistFitArgs>();
  auto* cmd = app.add_subcommand(
      "fit", "Fit the glTF metallic-roughness model (Blender 4's Principled BSDF, Standard Surface, OpenPBR) or Blender "
             "2.8-3.6's Principled BSDF to a map point, a model's material or a table file; write it for artists' tools (glTF, MaterialX, Blender; docs/EXPORT.md)");
  cmd->add_option("source", a->source, "Model file (.matlas), or a table file (.binary, .bsdf)")->required();
  add_point_options(*cmd, a->at, a->material);
  cmd->add_option("-o,--output", a->outputs,
                  "Output file, repeatable; the type from the extension: .gltf (glTF 2.0 material), .mtlx (MaterialX "
                  "1.39 document, OpenPBR Surface), .py (Blender script), .json (fit report), .binary (the fit as a MERL table)")
      ->required();
  cmd->add_option("--name", a->name, "Material name in the files (default: the material or file name)");
  cmd->add_option("--model", a->model,
                  "The model fitted: gltf (glTF metallic-roughness: glTF, MaterialX/OpenPBR, Blender 4's Principled "
                  "BSDF) or principled-v1 (Blender 2.8-3.6's Principled BSDF, as Cycles renders it: .py, .json, .binary)")
      ->check(CLI::IsMember({"gltf", "principled-v1"}))
      ->capture_default_str();
  cmd->callback([io, a] { run_fit(*a, io); });
}

}  // namespace

MATLAS_COMMAND(42, add_fit_command);

}  // namespace matlas::cli
