#pragma once
// The JavaScript charting library (Chart.js) inlined into evaluation reports so that they open
// offline. Found at build time (embedded into the library) or at run time.
#include <filesystem>
#include <string>

namespace matlas::eval {

struct ChartLibrary {
  std::string code;    ///< the library's JS source; empty when none was found
  std::string source;  ///< where it came from (a path), for the report's footer
};

/// The Chart.js browser build, looked up in this order: the file named by the environment variable
/// MATLAS_CHARTJS; the copy embedded at build time; <repo_root>/web/node_modules/chart.js/dist/
/// chart.umd.js (when repo_root is given); /usr/share/javascript/chart.js/chart.min.js (Debian's
/// libjs-chart.js). Returns an empty library when none exists (the report then shows tables only).
ChartLibrary find_chart_library(const std::filesystem::path& repo_root = {});

}  // namespace matlas::eval
