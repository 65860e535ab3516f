#include "artist/fit_report.h"

namespace matlas::artist {

namespace {

nlohmann::json rgb_json(const Rgb& c) { return {c[0], c[1], c[2]}; }

}  // namespace

nlohmann::json fit_report_json(const std::string& source, const PbrFitResult& fit, const FitError& e, double seconds,
                               std::optional<double> variance) {
  using nlohmann::json;
  const GltfPbr& m = fit.model;
  json albedo = json::array();
  for (std::size_t a = 0; a < e.angles_deg.size(); ++a)
    albedo.push_back({{"theta_deg", e.angles_deg[a]}, {"table", rgb_json(e.table_albedo[a])},
                      {"fit", rgb_json(e.fit_albedo[a])}});
  json r = {
      {"source", source},
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
        {"fuzz_roughness", m.sheen_roughness}}},
      {"error",
       {{"relative_rms", e.relative_rms}, {"cbrt_distance", e.cbrt_distance}, {"albedo_error", e.albedo_error},
        {"albedo", albedo}}},
      {"fit",
       {{"objective", fit.distance}, {"samples", fit.samples}, {"starts", fit.starts}, {"evaluations", fit.evaluations},
        {"converged", fit.converged()}, {"restart_gain", fit.restart_gain}, {"seconds", seconds}}}};
  if (variance) r["predictive_variance"] = *variance;
  return r;
}

}  // namespace matlas::artist
