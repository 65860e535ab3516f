// Sparse measurements: fit-samples (a full table from a handful of samples) and sample-plan (which
// directions to measure). docs/ACQUISITION.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "acquisition/model_samples.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"
#include "formats/sample_file.h"
#include "manifold/export.h"

namespace matlas::cli {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

json vector_of(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

json angles_of(const MeasuredSample& s) {
  const DirectionAngles i = direction_angles(s.wi), o = direction_angles(s.wo);
  return {{"theta_i", i.theta}, {"phi_i", i.phi}, {"theta_o", o.theta}, {"phi_o", o.phi}};
}

std::string where(const SampleFile& file, int line) { return (file.json ? "sample " : "line ") + std::to_string(line); }

// ---- fit-samples
struct FitArgs {
  std::string model, samples, output, report;
  bool json = false, skip_invalid = false, least_squares = false;
};

/// What fit-samples found, for --json and --report: the point, its uncertainty, the weights,
/// per sample the measured and predicted RGB, and what was unusable or skipped. `worst` receives
/// the largest residual in the fit's space.
json fit_report(const FitArgs& a, const Model& model, const SampleFile& file, const acquisition::ModelFit& result,
                const acquisition::SparseFitOptions& options, double seconds, double* worst_residual) {
  const acquisition::SparseFit& fit = result.fit;
  const std::vector<MeasuredSample> measured = file.measured();
  // Per sample: measured and predicted RGB, the residual in the fit's space, the rows' weight.
  json samples = json::array();
  std::vector<int> row_of(measured.size(), -1);
  const acquisition::SampleRows& rows = result.rows;  // sample: an index into `measured`
  for (Eigen::Index r = 0; r < rows.rows(); r += 3) row_of[static_cast<std::size_t>(rows.sample[static_cast<std::size_t>(r)])] = static_cast<int>(r);
  double worst = 0;
  for (std::size_t s = 0; s < measured.size(); ++s) {
    json j = angles_of(measured[s]);
    j["line"] = measured[s].line;
    j["measured"] = {measured[s].value[0], measured[s].value[1], measured[s].value[2]};
    const int r = row_of[s];
    if (r < 0) {
      j["usable"] = false;
    } else {
      j["predicted"] = {fit.predicted(r), fit.predicted(r + 1), fit.predicted(r + 2)};
      j["residual"] = {fit.residual(r), fit.residual(r + 1), fit.residual(r + 2)};
      j["weight"] = std::min({fit.weight(r), fit.weight(r + 1), fit.weight(r + 2)});
      worst = std::max(worst, fit.residual.segment(r, 3).cwiseAbs().maxCoeff());
    }
    samples.push_back(j);
  }
  std::vector<int> outlier_lines;
  for (int o : fit.outliers) outlier_lines.push_back(file.samples[static_cast<std::size_t>(o)].line);
  json weights = json::array();
  std::vector<int> order(static_cast<std::size_t>(model.count()));
  for (int i = 0; i < model.count(); ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(), [&](int p, int q) { return std::abs(result.weights(p)) > std::abs(result.weights(q)); });
  for (int i : order)
    if (std::abs(result.weights(i)) > 1e-9) weights.push_back({{"name", model.names()[static_cast<std::size_t>(i)]}, {"weight", result.weights(i)}});
  Eigen::VectorXd sigma = fit.latent_covariance.diagonal().cwiseMax(0).cwiseSqrt();
  json report = {{"model", a.model},
                 {"samples_file", a.samples},
                 {"x", vector_of(fit.x)},
                 {"latent_sigma", vector_of(sigma)},
                 {"latent_covariance", json::array()},
                 {"variance", fit.variance},
                 {"interpolation", to_string(model.interpolation())},
                 {"transform", options.transform.to_string()},
                 {"loss", options.robust ? "cauchy" : "least-squares"},
                 {"scale", fit.scale},
                 {"best_input", model.names()[static_cast<std::size_t>(fit.best_input)]},
                 {"combined", fit.combined},
                 {"combination_strength", fit.combined ? json(fit.combination_strength) : json(nullptr)},
                 {"weights", weights},
                 {"samples", samples},
                 {"outlier_lines", outlier_lines},
                 {"unusable", result.unusable},
                 {"skipped", file.skipped},
                 {"evaluations", fit.evaluations},
                 {"seconds", seconds}};
  for (Eigen::Index i = 0; i < fit.latent_covariance.rows(); ++i) report["latent_covariance"].push_back(vector_of(fit.latent_covariance.row(i).transpose()));
  *worst_residual = worst;
  return report;
}

/// The summary printed without --json.
void print_fit_summary(const FitArgs& a, const Io& io, const Model& model, const SampleFile& file,
                       const acquisition::ModelFit& result, const acquisition::SparseFitOptions& options,
                       const json& report, double worst) {
  const acquisition::SparseFit& fit = result.fit;
  const std::vector<MeasuredSample> measured = file.measured();
  const Eigen::VectorXd sigma = fit.latent_covariance.diagonal().cwiseMax(0).cwiseSqrt();
  const std::size_t weights = report["weights"].size();
  std::vector<int> outlier_lines;
  for (int o : fit.outliers) outlier_lines.push_back(file.samples[static_cast<std::size_t>(o)].line);
  std::string x, s;
  for (Eigen::Index d = 0; d < fit.x.size(); ++d) {
    x += (d ? "," : "") + std::to_string(fit.x(d));
    s += (d ? "," : "") + std::to_string(sigma(d));
  }
  print(io.out, "%s on %s\n  samples           %zu measured, %zu used", a.samples.c_str(), a.model.c_str(), measured.size(),
        measured.size() - result.unusable.size());
  if (!file.skipped.empty()) print(io.out, ", %zu invalid skipped", file.skipped.size());
  print(io.out, "\n  latent point      %s (1-sigma %s)\n  variance          %.4g (0 at the data, towards 1 far from it)\n"
                "  best single input %s\n  largest residual  %.4g (%s space)\n",
        x.c_str(), s.c_str(), fit.variance, model.names()[static_cast<std::size_t>(fit.best_input)].c_str(), worst,
        options.transform.to_string().c_str());
  if (fit.combined)
    print(io.out, "  table             a convex combination of %zu inputs near the point (held-out samples preferred it "
                  "to the map point; strength %g)\n", weights, fit.combination_strength);
  else
    print(io.out, "  table             the map point's (held-out samples preferred it to a free combination)\n");
  if (!outlier_lines.empty()) {
    std::string lines;
    for (int l : outlier_lines) lines += (lines.empty() ? "" : ", ") + where(file, l);
    print(io.out, "  outliers          %zu, ignored by the robust loss: %s\n", outlier_lines.size(), lines.c_str());
  }
  for (const auto& u : result.unusable) print(io.out, "  unusable          %s\n", u.c_str());
  for (const auto& k : file.skipped) print(io.out, "  skipped           %s\n", k.c_str());
  if (static_cast<int>(measured.size()) < 2 * model.dim() + 4)
    print(io.out, "  note: %zu samples pin a point of a %d-dimensional map down loosely; 10 or more are better\n",
          measured.size(), model.dim());
  if (!a.output.empty()) print(io.out, "  written           %s\n", a.output.c_str());
}

void run_fit_samples(const FitArgs& a, const Io& io) {
  if (a.output.empty() && a.report.empty() && !a.json)
    throw Error("nothing to write: give -o OUT.binary for the table, --report R.json, or --json");
  std::vector<fs::path> inputs{a.model, a.samples};
  if (!a.output.empty()) refuse_output_among_inputs(a.output, inputs);
  if (!a.report.empty()) refuse_output_among_inputs(a.report, inputs);
  const Model model = Model::open(a.model);
  SampleReadOptions ro;
  ro.skip_invalid = a.skip_invalid;
  const SampleFile file = read_samples(a.samples, ro);
  acquisition::SparseFitOptions options;
  options.transform = acquisition::model_transform(model);
  options.robust = !a.least_squares;
  acquisition::ModelFit result;
  const auto start = std::chrono::steady_clock::now();
  try {
    result = acquisition::fit_samples(model, file.samples, options);
  } catch (const Error& e) {
    throw file_error(a.samples, e.what());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double worst = 0;
  const json report = fit_report(a, model, file, result, options, seconds, &worst);
  if (!a.output.empty()) {
    ExportStats stats;
    write_merl(a.output, export_table(model, result.weights, &stats));
  }
  if (!a.report.empty()) write_file_atomic(a.report, report.dump(2));
  if (a.json) {
    print(io.out, "%s\n", report.dump(2).c_str());
    return;
  }
  print_fit_summary(a, io, model, file, result, options, report, worst);
}

// ---- sample-plan
struct PlanArgs {
  std::string model, output, given, simulate;
  int count = 20;
  bool skip_invalid = false;
};

void run_sample_plan(const PlanArgs& a, const Io& io) {
  std::vector<fs::path> inputs{a.model};
  if (!a.given.empty()) inputs.push_back(a.given);
  if (!a.simulate.empty()) inputs.push_back(a.simulate);
  refuse_output_among_inputs(a.output, inputs);
  const Model model = Model::open(a.model);
  std::vector<MeasuredSample> measured;
  if (!a.given.empty()) {
    SampleReadOptions ro;
    ro.skip_invalid = a.skip_invalid;
    measured = read_samples(a.given, ro).measured();
  }
  acquisition::PlanOptions options;
  options.transform = acquisition::model_transform(model);
  acquisition::ModelPlan plan = acquisition::plan_samples(model, a.count, measured, options);
  if (!a.simulate.empty()) {  // a simulated measurement: the table's values at the plan's bins
    const BrdfTable table = read_brdf(a.simulate);
    if (!(table.dims() == model.dims())) throw file_error(a.simulate, "its grid is not the model's");
    for (auto& s : plan.directions) {
      const std::size_t bin = bin_of(table.dims(), s.wi, s.wo);
      for (int c = 0; c < 3; ++c) s.value[c] = std::max(table.value(c, bin), 0.0);
      s.measured = true;
    }
  }
  std::vector<std::string> comment{
      "matlas sample-plan: " + std::to_string(plan.directions.size()) + " directions to measure for " +
          fs::path(a.model).filename().string() + " (" + std::to_string(model.count()) + " materials, q = " +
          std::to_string(model.dim()) + ")",
      plan.conditioned_on > 0 ? "the next directions given the " + std::to_string(plan.conditioned_on) +
                                    " samples measured in " + a.given
                              : "a fresh plan, best first: measure the rows in order",
      a.simulate.empty() ? "fill in r,g,b (BRDF values, 1/sr; or quantity 'ratio' for f cos(theta_i)) and, if known, "
                           "sigma_r,g,b; then matlas fit-samples MODEL THIS_FILE -o OUT.binary"
                         : "values simulated from " + a.simulate + " (its bins at these directions)"};
  write_file_atomic(a.output, format_samples_csv(plan.directions, comment));
  print(io.out, "%s: %zu directions%s\n  %3s %8s %8s %8s %8s %9s %10s\n", a.output.c_str(), plan.directions.size(),
        plan.conditioned_on > 0 ? (" given " + std::to_string(plan.conditioned_on) + " measured samples").c_str() : "",
        "#", "theta_i", "phi_i", "theta_o", "phi_o", "gain", "unexplained");
  for (std::size_t k = 0; k < plan.directions.size(); ++k) {
    const json j = angles_of(plan.directions[k]);
    print(io.out, "  %3zu %8.2f %8.2f %8.2f %8.2f %9.3f %9.1f%%\n", k + 1, j["theta_i"].get<double>(), j["phi_i"].get<double>(),
          j["theta_o"].get<double>(), j["phi_o"].get<double>(), plan.plan.gain[k], 100 * plan.plan.remaining[k]);
  }
}

void add_acquisition_commands(CLI::App& app, const Io& io) {
  {
    auto a = std::make_shared<FitArgs>();
    auto* cmd = app.add_subcommand(
        "fit-samples", "Fit a handful of measured BRDF samples (CSV or JSON) on the map: the full table, the latent "
                       "point and its uncertainty, residuals and outliers (docs/ACQUISITION.md)");
    cmd->add_option("model", a->model, "Model file (.matlas)")->required();
    cmd->add_option("samples", a->samples, "Samples file: CSV (theta_i,phi_i,theta_o,phi_o,r,g,b[,quantity][,sigma...]) or JSON")
        ->required();
    cmd->add_option("-o,--output", a->output, "The fitted table as a MERL .binary file");
    cmd->add_option("--report", a->report, "Write the fit as JSON (point, weights, per-sample residuals) to this file");
    cmd->add_flag("--json", a->json, "Print the JSON report instead of the summary");
    cmd->add_flag("--skip-invalid", a->skip_invalid, "Skip invalid samples (listed) instead of failing");
    cmd->add_flag("--least-squares", a->least_squares, "Plain least squares instead of the robust (Cauchy) loss");
    cmd->callback([io, a] { run_fit_samples(*a, io); });
  }
  {
    auto a = std::make_shared<PlanArgs>();
    auto* cmd = app.add_subcommand(
        "sample-plan", "The directions to measure for this map, best first, as a CSV to fill in (with --given: the "
                       "next ones after the samples measured so far)");
    cmd->add_option("model", a->model, "Model file (.matlas)")->required();
    cmd->add_option("-k,--count", a->count, "How many directions")->check(CLI::Range(1, 1000))->capture_default_str();
    cmd->add_option("-o,--output", a->output, "The plan (CSV)")->required();
    cmd->add_option("--given", a->given, "Samples measured so far (CSV or JSON): plan the next directions");
    cmd->add_flag("--skip-invalid", a->skip_invalid, "Skip invalid rows of --given instead of failing");
    cmd->add_option("--simulate", a->simulate,
                    "Fill the plan with this table's values (.binary or .bsdf): a simulated measurement, to try "
                    "the pipeline on a known material");
    cmd->callback([io, a] { run_sample_plan(*a, io); });
  }
}

}  // namespace

MATLAS_COMMAND(45, add_acquisition_commands);

}  // namespace matlas::cli
