#pragma once
// The evaluation report: REPORT_DIR/index.html (self-contained, opens offline: the data and the
// Chart.js library are inlined), report.json (everything), CSV tables and the plausibility maps as
// PNG images. docs/EVALUATION.md describes every number.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "eval/layout_study.h"
#include "eval/manifold_quality.h"
#include "eval/model_checks.h"

namespace matlas::eval {

struct ReportInput {
  std::string command;              ///< the command line that produced the report
  std::string input;                ///< the model or folder evaluated
  const StudyResult* study = nullptr;      ///< items 5-7 (may be null)
  const ModelChecks* checks = nullptr;     ///< items 1-4 (may be null)
  const ManifoldQuality* quality = nullptr;  ///< item 8 (may be null)
  std::string notes;                ///< free text shown at the top (e.g. why a part is missing)
  std::filesystem::path repo_root;  ///< where to look for web/node_modules/chart.js at run time
};

/// All results as JSON (the content of report.json).
nlohmann::json report_json(const ReportInput& input);

/// Writes the report files into `dir` (created if needed), each atomically. Throws matlas::Error
/// naming the file on failure.
void write_report(const std::filesystem::path& dir, const ReportInput& input);

}  // namespace matlas::eval
