#pragma once
// A fitted glTF metallic-roughness material (brdf/gltf_pbr.h) as a glTF 2.0 document that holds
// only the material (no scene, no mesh: a valid asset that glTF tools and importers read), with
// KHR_materials_specular for the specular factor, KHR_materials_clearcoat when there is a coat and
// KHR_materials_ior when the IOR is not 1.5.
#include <filesystem>
#include <string>

#include "brdf/gltf_pbr.h"

namespace matlas::artist {

/// The document's JSON text (2-space indented). `name` becomes the material's name; `source`
/// goes to the material's extras (what it was fitted to).
std::string gltf_material_document(const GltfPbr& model, const std::string& name, const std::string& source);

/// Writes the document atomically (core/atomic_file.h); throws matlas::Error naming the file.
void write_gltf_material(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                         const std::string& source);

}  // namespace matlas::artist
