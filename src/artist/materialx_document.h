#pragma once
// A fitted glTF metallic-roughness material (brdf/gltf_pbr.h) as a MaterialX 1.39 document: one
// `open_pbr_surface` node (OpenPBR Surface, the standard library's ND_open_pbr_surface_surfaceshader)
// and the `surfacematerial` that uses it, written with pugixml.
//
// Mapping (the shared core of the two models; docs/EXPORT.md, "MaterialX"):
//   base_color = base colour, base_metalness = metallic, specular_roughness = roughness (both
//   alpha = r^2, GGX), specular_weight = specular factor, specular_ior = IOR, base_weight = 1,
//   base_diffuse_roughness = 0 (Lambertian), coat_weight / coat_roughness = clearcoat and its
//   roughness, coat_ior = 1.5 (glTF's coat; OpenPBR's default is 1.6), coat_darkening = 0 (glTF's
//   coat does not darken the base).
// Not exact: OpenPBR's specular_weight scales F0 only (glTF scales F0 and F90, so the two agree at
// normal incidence), and OpenPBR's layering conserves energy where glTF mixes by (1 - F).
//
// MaterialX names are identifiers ([A-Za-z_][A-Za-z0-9_]*): the material's name is made one (other
// bytes become '_'); the name as given and what the fit was made of go to `doc` attributes.
#include <filesystem>
#include <string>

#include "brdf/gltf_pbr.h"

namespace matlas::artist {

/// `name` as a MaterialX identifier: every byte outside [A-Za-z0-9_] becomes '_', and a leading
/// digit (or an empty name) gets a leading "M_".
std::string materialx_identifier(const std::string& name);

/// The document's XML text. The nodes are named "SR_" + identifier (the shader) and the
/// identifier (the material).
std::string materialx_document(const GltfPbr& model, const std::string& name, const std::string& source);

/// Writes the document atomically (core/atomic_file.h); throws matlas::Error naming the file.
void write_materialx_document(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                              const std::string& source);

}  // namespace matlas::artist
