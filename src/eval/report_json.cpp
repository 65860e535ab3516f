#include "eval/report.h"

#include <chrono>
#include <cmath>
#include <ctime>

namespace matlas::eval {

namespace {

using nlohmann::json;

/// JSON number, or null for NaN / infinity (JSON has no such numbers).
json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json distance(const BrdfDistance& d) { return {{"cbrt", num(d.cbrt_cosine)}, {"rmse", num(d.cosine_rmse)}}; }

json matrix(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(num(m(i, j)));
    rows.push_back(row);
  }
  return rows;
}

json vector_json(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(num(x));
  return a;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

json study_json(const StudyResult& s) {
  json configs = json::array();
  for (const ConfigResult& c : s.configs) {
    json loo = json::array();
    for (const LooEntry& e : c.loo)
      loo.push_back({{"material", e.material}, {"gp", distance(e.gp)}, {"pca", distance(e.pca)},
                     {"nearest", distance(e.nearest)}, {"nearest_material", e.nearest_material},
                     {"layout_residual", num(e.gram_residual)}});
    json paths = json::array();
    for (const PathEntry& p : c.paths) {
      json steps = json::array();
      for (const auto& d : p.steps) steps.push_back(num(d.cbrt_cosine));
      paths.push_back({{"a", p.a}, {"b", p.b}, {"latent_distance", num(p.latent_distance)},
                       {"ends", distance(p.ends)}, {"steps_cbrt", steps}});
    }
    configs.push_back({{"layout", c.layout.to_string()},
                       {"dim", c.dim},
                       {"log_likelihood", num(c.log_likelihood)},
                       {"spearman_pairs", num(c.spearman_pairs)},
                       {"spearman_steps", num(c.spearman_steps)},
                       {"path_length_ratio", num(c.path_length_ratio)},
                       {"path_step_unevenness", num(c.path_step_unevenness)},
                       {"loo_mean", {{"gp", {{"cbrt", num(c.loo_gp_cbrt)}, {"rmse", num(c.loo_gp_rmse)}}},
                                     {"pca", {{"cbrt", num(c.loo_pca_cbrt)}, {"rmse", num(c.loo_pca_rmse)}}},
                                     {"nearest", {{"cbrt", num(c.loo_nearest_cbrt)}, {"rmse", num(c.loo_nearest_rmse)}}}}},
                       {"fit_seconds", num(c.fit_seconds)},
                       {"latent", matrix(c.latent)},
                       {"loo", loo},
                       {"paths", paths}});
  }
  json layouts = json::array();
  for (const auto& l : s.layouts) layouts.push_back(l.to_string());
  return {{"materials", s.names},
          {"dims", s.dims},
          {"layouts", layouts},
          {"kept_columns", s.kept_columns},
          {"compared_values", s.compared_values},
          {"value_stride", s.value_stride},
          {"recommended_layout", s.recommended.to_string()},
          {"recommendation", s.recommendation},
          {"material_cbrt", matrix(s.material_cbrt)},
          {"material_rmse", matrix(s.material_rmse)},
          {"configs", configs},
          {"seconds", {{"gram", num(s.gram_seconds)}, {"fits", num(s.fit_seconds)}, {"distances", num(s.pass_seconds)}}}};
}

json checks_json(const ModelChecks& m) {
  const InterpolationCheck& ic = m.interpolation;
  const PlausibilityMap& map = m.map;
  json albedo_rows = json::array();
  for (const auto& r : m.albedo.rows) albedo_rows.push_back(vector_json(r));
  return {{"model", m.model_path},
          {"count", m.count},
          {"dim", m.dim},
          {"layout", m.layout},
          {"interpolation", {{"available", ic.available}, {"note", ic.note}, {"materials", ic.materials},
                             {"max_abs_error", vector_json(ic.max_abs_error)},
                             {"mean_abs_error", vector_json(ic.mean_abs_error)},
                             {"max_relative_error", vector_json(ic.max_relative_error)},
                             {"max_weight_error", num(ic.max_weight_error)},
                             {"column_mismatches", ic.column_mismatches}}},
          {"reciprocity", {{"points", m.reciprocity.points}, {"pairs", m.reciprocity.pairs},
                           {"unequal", m.reciprocity.unequal},
                           {"max_relative_difference", num(m.reciprocity.max_relative_difference)}}},
          {"albedo", {{"angles_degrees", vector_json(m.albedo.angles_degrees)},
                      {"max_relative_error", num(m.albedo.max_relative_error)},
                      {"max_relative_error_clamped", num(m.albedo.max_relative_error_clamped)},
                      {"max_relative_error_model", num(m.albedo.max_relative_error_model)},
                      {"columns", {"point", "theta_o_deg", "channel", "exported_unclamped", "weighted_sum", "exported_clamped"}},
                      {"rows", albedo_rows}}},
          {"map", {{"resolution", map.resolution}, {"axis_x", map.axis_x}, {"axis_y", map.axis_y},
                   {"x_range", {num(map.x_min), num(map.x_max)}}, {"y_range", {num(map.y_min), num(map.y_max)}},
                   {"rows", m.dim > 1 ? map.resolution : 1},
                   {"negative_fraction", vector_json(map.negative_fraction)},
                   {"max_albedo", vector_json(map.max_albedo)},
                   {"variance", vector_json(map.variance)},
                   {"worst_negative_fraction", num(map.worst_negative_fraction)},
                   {"worst_max_albedo", num(map.worst_max_albedo)},
                   {"data_max_albedo", num(map.data_max_albedo)},
                   {"values", map.values},
                   {"export_clamped_at_worst", map.export_clamped_at_worst}}}};
}

}  // namespace

nlohmann::json report_json(const ReportInput& input) {
  json j = {{"generator", std::string("matlas ") + MATLAS_VERSION},
            {"created", utc_now()},
            {"command", input.command},
            {"input", input.input},
            {"notes", input.notes},
            {"metrics",
             {{"cbrt", "Fores et al. 2012 cube-root metric: sqrt(mean over values (cbrt(c f) - cbrt(c g))^2), "
                       "c = cos(theta_i) cos(theta_o) at the bin centre, signed cube root"},
              {"rmse", "cosine-weighted RMSE: sqrt(mean over values (c (f - g))^2), physical units"}}}};
  j["study"] = input.study ? study_json(*input.study) : json(nullptr);
  j["model_checks"] = input.checks ? checks_json(*input.checks) : json(nullptr);
  if (input.quality) {
    const ManifoldQuality& mq = *input.quality;
    json modes = json::array();
    for (const ModePlausibility& p : mq.plausibility)
      modes.push_back({{"mode", p.mode},
                       {"where", p.where},
                       {"points", p.points},
                       {"with_negative", p.with_negative},
                       {"value_stride", p.value_stride},
                       {"mean_negative_share", p.mean_negative_share},
                       {"worst_negative_share", p.worst_negative_share},
                       {"worst_albedo_ratio", p.worst_albedo_ratio},
                       {"most_negative_weight", p.most_negative_weight}});
    j["manifold_quality"] = {{"extent", mq.layout.extent},
                             {"crowded_share", mq.layout.crowded_share},
                             {"crowded", mq.layout.crowded},
                             {"trustworthiness", mq.layout.trustworthiness},
                             {"neighbours", mq.layout.neighbours},
                             {"inputs_max_albedo", mq.inputs_max_albedo},
                             {"input_negative_values", mq.input_negative_values},
                             {"plausibility", modes}};
  } else {
    j["manifold_quality"] = nullptr;
  }
  return j;
}

}  // namespace matlas::eval
