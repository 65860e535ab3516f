// matlas evaluate (MODEL | DIR) -o REPORT_DIR [--dims 2,3,5,8]: measures what the paper claims
// (exact interpolation, reciprocity, albedo linearity, plausibility over the map, perceptual
// distance along latent paths, leave-one-out against PCA and the nearest material, layout
// transforms) and writes an HTML report with the data as CSV/JSON (docs/EVALUATION.md).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/placement_options.h"
#include "cli/print.h"
#include "cli/world.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/progress.h"
#include "eval/layout_study.h"
#include "eval/manifold_quality.h"
#include "eval/model_checks.h"
#include "eval/report.h"
#include "eval/sparse_study.h"
#include "manifold/build.h"
#include "manifold/model_metadata.h"

namespace matlas::cli {

namespace {

namespace fs = std::filesystem;

struct EvaluateArgs {
  std::string input;
  std::string output;
  std::vector<int> dims{2, 3, 5, 8};
  std::vector<std::string> layouts;  // empty = all six
  int materials = -1;  // -1: automatic (eval::automatic_held_out for the study, 24 for --sparse)
  int pairs = 20;
  int segments = 8;
  int stride = 0;
  int map_resolution = 32;
  int interpolation_materials = eval::ModelCheckOptions::kInterpolationMaterials;
  int model_dim = 2;
  bool skip_study = false;
  bool sparse = false;
  std::vector<int> sparse_counts{5, 10, 20, 40, 80};
  int candidates = 1500;
  bool skip_checks = false;
  std::string interpolation = "convex";
  gp::SparseOptions placement{};  ///< the fits' placement: exact unless --sparse-inducing
  bool quiet = false;
  std::string command_line;
};

/// A model file removed when this goes out of scope (the temporary model of a folder evaluation).
struct TemporaryModel {
  fs::path path;
  ~TemporaryModel() {
    std::error_code ec;
    if (!path.empty()) fs::remove(path, ec);
  }
};

/// The source files listed in a model's metadata, if they all still exist.
std::vector<fs::path> model_sources(const Model& model) {
  std::vector<fs::path> files;
  const auto& meta = model.metadata();
  if (!meta.contains("sources") || !meta["sources"].is_array()) return {};
  for (const auto& s : meta["sources"]) {
    const fs::path p = s.value("path", std::string());
    std::error_code ec;
    if (p.empty() || !fs::is_regular_file(p, ec)) return {};
    files.push_back(p);
  }
  return files;
}

void print_summary(const eval::StudyResult* study, const eval::ModelChecks* checks,
                   const eval::ManifoldQuality* quality, const Io& io) {
  if (quality) {
    print(io.out, "  layout readability    %.1f%% of materials crowded (neighbour < 1%% of extent %.3g); trustworthiness(%d) %.3f\n",
                100 * quality->layout.crowded_share, quality->layout.extent, quality->layout.neighbours,
                quality->layout.trustworthiness);
    for (const auto& p : quality->plausibility)
      print(io.out, "  plausibility %-6s %-9s %d of %d points with negative values (worst %.3f%%%s), albedo / inputs' max %.3f\n",
                  p.mode.c_str(), p.where.c_str(), p.with_negative, p.points, 100 * p.worst_negative_share,
                  p.value_stride > 1 ? (", value stride " + std::to_string(p.value_stride)).c_str() : "",
                  p.worst_albedo_ratio);
  }
  if (checks) {
    const auto& ic = checks->interpolation;
    double worst = 0;
    for (double v : ic.max_relative_error) worst = std::max(worst, v);
    if (ic.available)
      print(io.out, "  exact interpolation   max error / peak %.3g (weights %.3g; %zu of %d materials)\n", worst,
            ic.max_weight_error, ic.materials.size(), checks->count);
    print(io.out, "  reciprocity           %zu of %d direction pairs differ (max rel. %.3g)\n", checks->reciprocity.unequal,
                checks->reciprocity.pairs, checks->reciprocity.max_relative_difference);
    print(io.out, "  albedo linearity      max rel. error %.3g (after the export clamp %.3g)\n",
                checks->albedo.max_relative_error, checks->albedo.max_relative_error_clamped);
    print(io.out, "  plausibility map      negative values up to %.3f%%, largest albedo %.3f (inputs %.3f)\n",
                100 * checks->map.worst_negative_fraction, checks->map.worst_max_albedo, checks->map.data_max_albedo);
  }
  if (study) {
    print(io.out, "  recommended layout    %s\n", study->recommendation.c_str());
    print(io.out, "  %-14s %3s %10s %10s %10s %9s\n", "layout", "q", "LOO matlas", "LOO PCA", "nearest", "Spearman");
    for (const auto& c : study->configs)
      print(io.out, "  %-14s %3d %10.4f %10.4f %10.4f %9.3f\n", c.layout.to_string().c_str(), c.dim, c.loo_gp_cbrt,
                  c.loo_pca_cbrt, c.loo_nearest_cbrt, c.spearman_pairs);
  }
}

/// `evaluate --sparse`: the leave-one-out study of sparse reconstruction only.
void run_sparse_evaluation(const EvaluateArgs& a, const MaterialSet& set, TerminalProgress& progress, const Io& io) {
  eval::SparseStudyOptions so;
  so.counts = a.sparse_counts;
  so.dim = a.model_dim;
  so.materials = a.materials >= 0 ? a.materials : 24;
  so.candidates = a.candidates;
  if (!a.layouts.empty()) so.layout = LayoutTransform::parse(a.layouts.front());
  if (interpolation_from_string(a.interpolation) == Interpolation::gp) so.fit.convex_ridge = 0;
  so.fit.sparse = a.placement;
  if (!a.quiet)
    print(io.err, "sparse reconstruction: %zu materials, each left out in turn (q = %d, %s)\n", set.size(), so.dim,
          so.layout.to_string().c_str());
  const eval::SparseStudy study = eval::run_sparse_study(set, so, progress);
  const fs::path out = a.output;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw file_error(out, "cannot create the report folder: " + ec.message());
  nlohmann::json j = eval::sparse_study_json(study);
  j["command"] = a.command_line;
  write_file_atomic(out / "sparse.json", j.dump(1));
  std::string csv = "method,count,mean,median,ridge\n";
  for (const auto& r : study.results)
    csv += r.method + "," + std::to_string(r.count) + "," + std::to_string(r.mean) + "," + std::to_string(r.median) + "," +
           (r.method.rfind("pca", 0) == 0 ? std::to_string(r.ridge) : std::string()) + "\n";
  write_file_atomic(out / "sparse.csv", csv);
  print(io.out, "wrote %s\n  cube-root distance to the left-out table (mean over %zu materials, maps of %d inputs, q = %d)\n",
        (out / "sparse.json").string().c_str(), study.materials.size(), study.inputs, study.dim);
  print(io.out, "  %5s %15s %15s %15s %15s\n", "K", "matlas-planned", "matlas-random", "pca-condition", "pca-random");
  for (int c : a.sparse_counts)
    print(io.out, "  %5d %15.4f %15.4f %15.4f %15.4f\n", c, study.find("matlas-planned", c).mean,
          study.find("matlas-random", c).mean, study.find("pca-condition", c).mean, study.find("pca-random", c).mean);
  print(io.out, "  nearest other material (reference): %.4f\n", study.nearest_input);
  print(io.out, "  robustness at K = %d: clean %.4f, %d%% of samples x10: %.4f (robust), %.4f (least squares)\n",
        study.robustness_count, study.clean, 10, study.corrupted, study.corrupted_least_squares);
  print(io.out, "  one fit at K = %d: %.3f s; the study: %.0f s\n", *std::max_element(a.sparse_counts.begin(), a.sparse_counts.end()),
        study.fit_seconds, study.seconds);
}

void run_evaluate(const EvaluateArgs& a, const Io& io) {
  // Under mpirun every rank opens the database and takes its share of the study (its Gram and
  // distance passes read a share of every file, its fits a share of the jobs); rank 0 then runs
  // the model checks and writes the report alone.
  Communicator& comm = world();
  const bool root = comm.is_root();
  TerminalProgress progress(!a.quiet && root);
  const fs::path input = a.input, out = a.output;
  if (a.sparse && comm.size() > 1)
    throw Error("--sparse runs in one process: run it without mpirun (or with -np 1)");

  eval::StudyOptions so;
  so.dims = a.dims;
  if (!a.layouts.empty()) {
    so.layouts.clear();
    for (const auto& l : a.layouts) so.layouts.push_back(LayoutTransform::parse(l));
  }
  so.pairs = a.pairs;
  so.path_segments = a.segments;
  so.value_stride = a.stride;
  if (interpolation_from_string(a.interpolation) == Interpolation::gp) so.fit.convex_ridge = 0;
  so.fit.sparse = a.placement;
  eval::ModelCheckOptions co;
  co.map_resolution = a.map_resolution;
  co.interpolation_materials = a.interpolation_materials;

  std::unique_ptr<MaterialSet> set;
  std::unique_ptr<Model> model;
  TemporaryModel temporary;
  std::string notes;
  run_collectively(comm, [&] {
    std::error_code ec;
    if (!fs::exists(input, ec)) throw file_error(input, "no such model or folder");
    refuse_output_among_inputs(out, {input});  // the report folder: not the model, nor the database
    if (fs::is_directory(input, ec)) {
      set = std::make_unique<MaterialSet>(MaterialSet::open({input}));
    } else {
      model = std::make_unique<Model>(Model::open(input));
      const std::vector<fs::path> sources = model_sources(*model);
      if (!sources.empty()) set = std::make_unique<MaterialSet>(MaterialSet::open(sources));
      else notes = "The model's source files are not available: only the checks of the model itself were run.";
    }
  });

  if (a.sparse) {
    if (!set) throw file_error(input, "--sparse needs the database: a folder, or a model whose source files are present");
    run_sparse_evaluation(a, *set, progress, io);
    return;
  }

  std::unique_ptr<eval::StudyResult> study;
  if (set && !a.skip_study) {
    so.materials = a.materials >= 0 ? a.materials : eval::automatic_held_out(set->size());
    if (!a.quiet && root) {
      print(io.err, "evaluating %zu materials: q in {%s}, %zu layouts, %zu left out in turn (--materials)", set->size(),
            [&] { std::string s; for (int q : so.dims) s += (s.empty() ? "" : ",") + std::to_string(q); return s; }().c_str(),
            so.layouts.size(), so.materials > 0 ? std::min<std::size_t>(static_cast<std::size_t>(so.materials), set->size()) : set->size());
      if (comm.size() > 1) print(io.err, " on %d MPI ranks", comm.size());
      print(io.err, "\n");
    }
    run_collectively(comm, [&] { study = std::make_unique<eval::StudyResult>(eval::run_layout_study(*set, so, progress, comm)); });
  }

  // Rank 0 alone from here; the others wait for its outcome (a failure ends every rank with it).
  run_collectively(comm, [&] {
    if (!root) return;
    std::unique_ptr<eval::ModelChecks> checks;
    std::unique_ptr<eval::ManifoldQuality> quality;
    if (!a.skip_checks) {
      if (!model) {
        // A folder: build a model the way `matlas build` does (recommended layout, q = --model-dim).
        BuildOptions bo;
        bo.dim = a.model_dim;
        bo.interpolation = interpolation_from_string(a.interpolation);
        if (study) bo.layout = study->recommended;
        temporary.path = fs::temp_directory_path() / ("matlas-evaluate-" + std::to_string(::getpid()) + ".matlas");
        progress.message("building a q=" + std::to_string(bo.dim) + " model (" + bo.layout.to_string() + ") for the model checks");
        build_model(*set, bo, temporary.path, progress);
        model = std::make_unique<Model>(Model::open(temporary.path));
        notes += (notes.empty() ? "" : " ") + std::string("Items 1-4 were measured on a q=") + std::to_string(bo.dim) +
                 " model built from the folder with layout " + bo.layout.to_string() + ".";
      }
      checks = std::make_unique<eval::ModelChecks>(eval::run_model_checks(*model, set.get(), co, progress));
      quality = std::make_unique<eval::ManifoldQuality>(eval::assess_manifold(*model, {}, progress));
    }

    eval::ReportInput ri;
    ri.command = a.command_line;
    ri.input = fs::absolute(input).string();
    ri.study = study.get();
    ri.checks = checks.get();
    ri.quality = quality.get();
    ri.notes = notes;
    ri.repo_root = fs::current_path();
    eval::write_report(out, ri);
    print(io.out, "wrote %s\n", (out / "index.html").string().c_str());
    print_summary(study.get(), checks.get(), quality.get(), io);
  });
}

void add_evaluate_command(CLI::App& app, const Io& io) {
  auto args = std::make_shared<EvaluateArgs>();
  auto* cmd = app.add_subcommand("evaluate", "Measure a model or a database (interpolation, plausibility, "
                                             "leave-one-out, latent paths, layouts) and write an HTML report");
  cmd->add_option("input", args->input, "A .matlas model or a folder of MERL .binary files")->required();
  cmd->add_option("-o,--output", args->output, "Report folder (index.html, report.json, CSV, PNG)")->required();
  cmd->add_option("--dims", args->dims, "Latent dimensions to evaluate")->delimiter(',')->check(CLI::Range(1, 10))->capture_default_str();
  cmd->add_option("--layouts", args->layouts, "Layout transforms to compare (default: all six: linear, cbrt, log, "
                                              "each also cosine-)")->delimiter(',');
  cmd->add_option("--materials", args->materials,
                  "Leave out only this many materials in turn, spread evenly over the list (0 = all: the full "
                  "study, one fit per material per layout and q). Default: 24, and past 50 materials 1200/n (at "
                  "least 8: 12 for 100 materials); 24 with --sparse")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--pairs", args->pairs, "Material pairs for latent paths")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--segments", args->segments, "Segments per latent path")->check(CLI::Range(1, 100))->capture_default_str();
  cmd->add_option("--stride", args->stride,
                  "Use every STRIDE-th value for perceptual distances; 0 (default): chosen so that the pass "
                  "compares at most 1e9 values (a minute or two on 2 cores); 1: every value (the full study)")
      ->check(CLI::Range(0, 1000))->capture_default_str();
  cmd->add_option("--interpolation-materials", args->interpolation_materials,
                  "Materials whose exact interpolation is checked (item 1), spread evenly over the list; 0 = all "
                  "(its cost grows as n times this)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--map-resolution", args->map_resolution, "Grid cells per axis of the plausibility map")
      ->check(CLI::Range(2, 256))->capture_default_str();
  cmd->add_option("--model-dim", args->model_dim, "q of the model built for the model checks when DIR is given")
      ->check(CLI::Range(1, 10))->capture_default_str();
  cmd->add_option("--interpolation", args->interpolation,
                  "Interpolation mode of the leave-one-out, the latent paths and the model built from a folder: "
                  "convex (default) or gp")
      ->capture_default_str();
  cmd->add_flag("--no-study", args->skip_study, "Skip items 5-7 (paths, leave-one-out, layouts)");
  cmd->add_flag("--sparse", args->sparse,
                "Only the sparse-reconstruction study (docs/ACQUISITION.md): each material left out, K samples at "
                "planned and random directions fitted on the map without it, against PCA (Nielsen et al. 2015); "
                "writes sparse.json and sparse.csv. Uses --materials, --model-dim (q), --interpolation and the first "
                "of --layouts");
  cmd->add_option("--sparse-counts", args->sparse_counts, "--sparse: sample counts K")
      ->delimiter(',')->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--candidates", args->candidates, "--sparse: candidate directions (a random subset of the plan's lattice)")
      ->check(CLI::Range(10, 100000))->capture_default_str();
  add_sparse_placement_options(*cmd, args->placement);  // the fits of the study (items 5-7) and of --sparse
  cmd->add_flag("--no-checks", args->skip_checks, "Skip items 1-4 (checks of a model)");
  cmd->add_flag("--quiet", args->quiet, "No progress output");
  cmd->callback([io, args, cmd] {
    args->command_line = "matlas evaluate";
    for (const auto& o : cmd->get_options())
      if (o->count() > 0) {
        if (o->get_name() == "input") args->command_line += " " + args->input;
        else {
          std::string values;  // every value given (a vector option has several)
          for (const auto& r : o->results()) values += (values.empty() ? "" : ",") + r;
          args->command_line += " " + o->get_name(false, true).substr(0, o->get_name(false, true).find(',')) +
                                (o->get_expected_min() > 0 ? " " + values : "");
        }
      }
    run_evaluate(*args, io);
  });
}

}  // namespace

MATLAS_COMMAND(70, add_evaluate_command);

}  // namespace matlas::cli
