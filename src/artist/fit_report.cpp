#include "artist/fit_report.h"

#include "core/error.h"

namespace matlas::artist {

namespace {

nlohmann::json rgb_json(const Rgb& c) { return {c[0], c[1], c[2]}; }

/// The report's parts that do not depend on the model: "error" and "fit" (and the variance).
template <class Fitted>
void add_fit_and_error(nlohmann::json& r, const AnalyticFit<Fitted>& fit, const FitError& e, double seconds,
                       std::optional<double> variance) {
  using nlohmann::json;
  json albedo = json::array();
  for (std::size_t a = 0; a < e.angles_deg.size(); ++a)
    albedo.push_back({{"theta_deg", e.angles_deg[a]}, {"table", rgb_json(e.table_albedo[a])},
                      {"fit", rgb_json(e.fit_albedo[a])}});
  r["error"] = {{"relative_rms", e.relative_rms}, {"cbrt_distance", e.cbrt_distance}, {"albedo_error", e.albedo_error},
                {"albedo", albedo}};
  r["fit"] = {{"objective", fit.distance}, {"samples", fit.samples}, {"starts", fit.starts}, {"evaluations", fit.evaluations},
              {"converged", fit.converged()}, {"restart_gain", fit.restart_gain}, {"seconds", seconds}};
  if (variance) r["predictive_variance"] = *variance;
}

}  // namespace

nlohmann::json fit_report_json(const std::string& source, const PbrFitResult& fit, const FitError& e, double seconds,
                               std::optional<double> variance) {
  using nlohmann::json;
  const GltfPbr& m = fit.model;
  json r = {
      {"source", source},
      {"kind", "gltf"},
      {"model", "glTF 2.0 metallic-roughness with KHR_materials_specular, KHR_materials_sheen and "
                "KHR_materials_clearcoat (docs/EXPORT.md)"},
      {"parameters",
       {{"base_color", rgb_json(m.base_color)}, {"metallic", m.metallic}, {"roughness", m.roughness},
        {"specular", m.specular}, {"ior", m.ior}, {"clearcoat", m.clearcoat},
        {"clearcoat_roughness", m.clearcoat_roughness}, {"sheen_color", rgb_json(m.sheen_color)},
        {"sheen_roughness", m.sheen_roughness}}},
      // The same parameters under OpenPBR Surface's / Standard Surface's names (the shared core of
      // the models: base colour, metalness, GGX roughness r, specular weight, IOR; the MaterialX
      // document's inputs, artist/materialx_document.h).
      {"openpbr_surface",
       {{"base_color", rgb_json(m.base_color)}, {"base_metalness", m.metallic}, {"specular_roughness", m.roughness},
        {"specular_weight", m.specular}, {"specular_ior", m.ior}, {"coat_weight", m.clearcoat},
        {"coat_roughness", m.clearcoat_roughness}, {"coat_ior", 1.5},
        {"fuzz_weight", m.sheen_color.maxCoeff() > 0 ? 1.0 : 0.0}, {"fuzz_color", rgb_json(m.sheen_color)},
        {"fuzz_roughness", m.sheen_roughness}}}};
  add_fit_and_error(r, fit, e, seconds, variance);
  return r;
}

nlohmann::json fit_report_json(const std::string& source, const PrincipledV1FitResult& fit, const FitError& e,
                               double seconds, std::optional<double> variance) {
  const PrincipledV1& m = fit.model;
  nlohmann::json r = {
      {"source", source},
      {"kind", "principled-v1"},
      {"model", "Blender 2.8-3.6 Principled BSDF (Cycles' Principled v1, GGX distribution) with a coat layer "
                "(docs/EXPORT.md)"},
      {"parameters",
       {{"base_color", rgb_json(m.base_color)}, {"metallic", m.metallic}, {"specular", m.specular},
        {"specular_tint", m.specular_tint}, {"roughness", m.roughness}, {"sheen", m.sheen},
        {"sheen_tint", m.sheen_tint}, {"coat", m.coat}, {"coat_roughness", m.coat_roughness}}}};
  add_fit_and_error(r, fit, e, seconds, variance);
  return r;
}

namespace {

/// A report's parameter: a number (or, for `rgb`, three), else an error naming it.
double number_at(const nlohmann::json& p, const char* name, const std::string& what) {
  const auto it = p.find(name);
  if (it == p.end() || !it->is_number()) throw Error(what + ": the fit's parameter '" + name + "' is missing or not a number");
  return it->get<double>();
}

Rgb rgb_at(const nlohmann::json& p, const char* name, const std::string& what) {
  const auto it = p.find(name);
  if (it == p.end() || !it->is_array() || it->size() != 3 || !(*it)[0].is_number() || !(*it)[1].is_number() ||
      !(*it)[2].is_number())
    throw Error(what + ": the fit's parameter '" + name + "' is missing or not three numbers");
  return Rgb((*it)[0].get<double>(), (*it)[1].get<double>(), (*it)[2].get<double>());
}

}  // namespace

BrdfFunction fitted_brdf(const nlohmann::json& report, const std::string& what) {
  if (!report.is_object() || !report.contains("parameters") || !report["parameters"].is_object())
    throw Error(what + ": not a fit report of matlas fit (no \"parameters\" object)");
  const nlohmann::json& p = report["parameters"];
  const std::string kind = report.contains("kind") && report["kind"].is_string() ? report["kind"].get<std::string>() : "gltf";
  try {
    if (kind == "gltf") {
      GltfPbr m;
      m.base_color = rgb_at(p, "base_color", what);
      m.metallic = number_at(p, "metallic", what);
      m.roughness = number_at(p, "roughness", what);
      m.specular = number_at(p, "specular", what);
      m.ior = number_at(p, "ior", what);
      m.clearcoat = number_at(p, "clearcoat", what);
      m.clearcoat_roughness = number_at(p, "clearcoat_roughness", what);
      m.sheen_color = rgb_at(p, "sheen_color", what);
      m.sheen_roughness = number_at(p, "sheen_roughness", what);
      m.validate();
      return m;
    }
    if (kind == "principled-v1") {
      PrincipledV1 m;
      m.base_color = rgb_at(p, "base_color", what);
      m.metallic = number_at(p, "metallic", what);
      m.specular = number_at(p, "specular", what);
      m.specular_tint = number_at(p, "specular_tint", what);
      m.roughness = number_at(p, "roughness", what);
      m.sheen = number_at(p, "sheen", what);
      m.sheen_tint = number_at(p, "sheen_tint", what);
      m.coat = number_at(p, "coat", what);
      m.coat_roughness = number_at(p, "coat_roughness", what);
      m.validate();
      return m;
    }
  } catch (const Error& e) {
    const std::string message = e.what();
    if (message.rfind(what, 0) == 0) throw;
    throw Error(what + ": " + message);
  }
  throw Error(what + ": unknown fit kind '" + kind + "' (expected gltf or principled-v1)");
}

}  // namespace matlas::artist
