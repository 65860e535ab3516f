// Queries of a built model: export (a point as a MERL file; `eval` is its deprecated alias), latent,
// weights, project.
#include <algorithm>
#include <cstdio>
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
#include "manifold/export.h"
#include "formats/rgl_bsdf.h"
#include "manifold/project.h"

namespace matlas::cli {

namespace {

using nlohmann::json;

json vector_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

std::string point_text(const Eigen::VectorXd& x) {
  std::string s;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (i > 0) s += ',';
    s += std::to_string(x[i]);
  }
  return s;
}

// ---- export
struct ExportArgs {
  std::string model, output;
  std::optional<std::string> at, material;
};

void run_export(const ExportArgs& a, const Io& io) {
  if (a.output.empty()) throw Error("-o: the output file name is empty");
  refuse_output_among_inputs(a.output, {a.model});
  const Model model = Model::open(a.model);
  const Eigen::VectorXd x = resolve_point(model, a.at, a.material);
  const Eigen::VectorXd w = a.material ? model.material_weights(model.index_of(*a.material)) : model.weights(x);
  ExportStats stats;
  const BrdfTable table = export_table(model, w, &stats);
  write_merl(a.output, table);
  print(io.out, "wrote %s (x = %s, predictive variance %.3g)\n", a.output.c_str(), point_text(x).c_str(),
              model.variance(x));
  if (stats.clamped)
    print(io.out, "  clamped %zu negative values to 0 (most negative %.3g)\n", stats.clamped, stats.most_negative);
  if (stats.missing) print(io.out, "  %zu values written as missing (-1): not measured in every input\n", stats.missing);
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
        "export", "Export the BRDF at a latent point as a MERL .binary file (alias: eval, deprecated)");
    cmd->alias("eval");  // the command's old name, kept for scripts written before the rename
    cmd->add_option("model", a->model, "Model file (.matlas)")->required();
    add_point_options(*cmd, a->at, a->material);
    cmd->add_option("-o,--output", a->output, "Output .binary file")->required();
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
