#pragma once
// The report of a fit (artist/pbr_fit.h) and its error (artist/fit_error.h) as JSON: what
// `matlas fit -o X.json` writes and POST /api/fit answers (docs/EXPORT.md, docs/API.md).
//
//   {"source", "kind" ("gltf" or "principled-v1"), "model" (its description), "parameters": {base_color, metallic, roughness, specular, ior, clearcoat,
//    clearcoat_roughness}, "openpbr_surface": {the same under OpenPBR Surface's names},
//    "error": {relative_rms, cbrt_distance, albedo_error, albedo: [{theta_deg, table, fit}]},
//    "fit": {objective, samples, starts, evaluations, converged, restart_gain, seconds},
//    ["predictive_variance"]}
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "artist/fit_error.h"
#include "artist/pbr_fit.h"
#include "brdf/tabulate.h"

namespace matlas::artist {

/// `source` says what was fitted; `seconds` the fit's time; `variance` the map point's predictive
/// variance (absent for a table file or a model's own material).
nlohmann::json fit_report_json(const std::string& source, const PbrFitResult& fit, const FitError& error,
                               double seconds, std::optional<double> variance);
/// The same for a fit of Blender 2.8-3.6's Principled BSDF: "model" names it, "parameters" are its
/// inputs (base_color, metallic, specular, specular_tint, roughness, sheen, sheen_tint) and the coat
/// layer's (coat, coat_roughness), no "openpbr_surface".
nlohmann::json fit_report_json(const std::string& source, const PrincipledV1FitResult& fit, const FitError& error,
                               double seconds, std::optional<double> variance);

}  // namespace matlas::artist

namespace matlas::artist {

/// The fitted model of a report (fit_report_json) as a BRDF, for rendering the fit itself: "kind"
/// gltf (also when absent, as in reports written before it existed) or principled-v1, with its
/// "parameters" checked. Throws matlas::Error starting with `what` (the file) when the JSON is not
/// a fit report or a parameter is missing or out of range.
BrdfFunction fitted_brdf(const nlohmann::json& report, const std::string& what);

}  // namespace matlas::artist
