#include "artist/gltf_material.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"

namespace matlas::artist {

namespace {

/// Six significant digits: what a material editor shows, and stable text in files.
double rounded(double v) {
  if (v == 0.0) return 0.0;
  const double scale = std::pow(10.0, 5 - static_cast<int>(std::floor(std::log10(std::abs(v)))));
  return std::round(v * scale) / scale;
}

}  // namespace

std::string gltf_material_document(const GltfPbr& m, const std::string& name, const std::string& source) {
  using nlohmann::json;
  json material;
  material["name"] = name;
  material["pbrMetallicRoughness"] = {
      {"baseColorFactor", {rounded(m.base_color[0]), rounded(m.base_color[1]), rounded(m.base_color[2]), 1.0}},
      {"metallicFactor", rounded(m.metallic)},
      {"roughnessFactor", rounded(m.roughness)}};
  json used = json::array({"KHR_materials_specular"});
  material["extensions"]["KHR_materials_specular"] = {{"specularFactor", rounded(m.specular)}};
  if (m.clearcoat > 0) {
    material["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", rounded(m.clearcoat)},
                                                         {"clearcoatRoughnessFactor", rounded(m.clearcoat_roughness)}};
    used.push_back("KHR_materials_clearcoat");
  }
  if (m.sheen_color.maxCoeff() > 0) {
    material["extensions"]["KHR_materials_sheen"] = {
        {"sheenColorFactor", {rounded(m.sheen_color[0]), rounded(m.sheen_color[1]), rounded(m.sheen_color[2])}},
        {"sheenRoughnessFactor", rounded(m.sheen_roughness)}};
    used.push_back("KHR_materials_sheen");
  }
  if (m.ior != 1.5) {
    material["extensions"]["KHR_materials_ior"] = {{"ior", rounded(m.ior)}};
    used.push_back("KHR_materials_ior");
  }
  material["extras"] = {{"matlas_fit_of", source}};
  const json doc = {{"asset", {{"version", "2.0"}, {"generator", "matlas fit"}}},
                    {"extensionsUsed", used},
                    {"materials", json::array({material})}};
  // Invalid UTF-8 in a name (a file name) is replaced, never an exception.
  return doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

void write_gltf_material(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                         const std::string& source) {
  AtomicFile file(path);
  file.write(gltf_material_document(model, name, source));
  file.commit();
}

}  // namespace matlas::artist
