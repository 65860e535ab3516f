#pragma once
// A fitted glTF metallic-roughness material (brdf/gltf_pbr.h) as a Blender Python script that
// builds the equivalent Principled BSDF material and assigns it to the active mesh object, for
// Blender 2.8 to 4.x (the specular input was renamed in 4.0).
//
// Mapping: base colour, metallic and roughness carry over unchanged (Blender's roughness is the
// same r, alpha = r^2); IOR as fitted; the specular factor s becomes "Specular IOR Level" = s / 2
// (4.x) or "Specular" = s / 2 (older; 0.5 is F0 = 0.04 in both). Blender scales F0 only, glTF F0
// and F90: the two agree at normal incidence. The clearcoat goes to "Coat Weight" / "Coat Roughness"
// (4.x: GGX, IOR 1.5 as glTF's); before 4.0 the Principled BSDF's "Clearcoat" is Disney's (a GTR1
// lobe at a quarter of the weight), so the script builds the coat as a layer instead: a GGX Glossy
// BSDF mixed over the Principled BSDF by clearcoat x Fresnel(n.v, IOR 1.5). Both are approximate
// in Blender 2.8-3.6, whose Principled BSDF is not the glTF model (docs/EXPORT.md, "In Blender").
//
// A fit of that Principled BSDF itself (brdf/principled_v1.h, `matlas fit --model principled-v1`)
// is written as its inputs, with the "GGX" distribution it was fitted with, and its coat as a second
// Principled BSDF (black, Specular 0.5) mixed in at the coat's weight and added; the script refuses
// to run in Blender 4, whose Principled BSDF is another model.
#include <filesystem>
#include <string>

#include "brdf/gltf_pbr.h"
#include "brdf/principled_v1.h"

namespace matlas::artist {

/// The script's text. `name` is the Blender material's name, `source` a comment.
std::string blender_snippet(const GltfPbr& model, const std::string& name, const std::string& source);
std::string blender_snippet(const PrincipledV1& model, const std::string& name, const std::string& source);

/// Writes the script atomically; throws matlas::Error naming the file.
void write_blender_snippet(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                           const std::string& source);
void write_blender_snippet(const std::filesystem::path& path, const PrincipledV1& model, const std::string& name,
                           const std::string& source);

}  // namespace matlas::artist
