#pragma once
// The report of a fit (artist/pbr_fit.h) and its error (artist/fit_error.h) as JSON: what
// `matlas fit -o X.json` writes and POST /api/fit answers (docs/EXPORT.md, docs/API.md).
//
//   {"source", "model", "parameters": {base_color, metallic, roughness, specular, ior, clearcoat,
//    clearcoat_roughness}, "openpbr_surface": {the same under OpenPBR Surface's names},
//    "error": {relative_rms, cbrt_distance, albedo_error, albedo: [{theta_deg, table, fit}]},
//    "fit": {objective, samples, starts, evaluations, converged, restart_gain, seconds},
//    ["predictive_variance"]}
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "artist/fit_error.h"
#include "artist/pbr_fit.h"

namespace matlas::artist {

/// `source` says what was fitted; `seconds` the fit's time; `variance` the map point's predictive
/// variance (absent for a table file or a model's own material).
nlohmann::json fit_report_json(const std::string& source, const PbrFitResult& fit, const FitError& error,
                               double seconds, std::optional<double> variance);

}  // namespace matlas::artist
