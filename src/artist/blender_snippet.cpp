#include "artist/blender_snippet.h"

#include <cstdio>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"

namespace matlas::artist {

namespace {

/// A Python string literal: a JSON string with every non-ASCII character escaped is one.
std::string python_string(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// "(r, g, b, 1.0)": a colour socket's value.
std::string colour(const Rgb& c) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g, 1.0)", c[0], c[1], c[2]);
  return buf;
}

/// The script's opening: the comment lines (what made it, what it was fitted to, how to run it),
/// `import bpy` and, after `guard` (version checks), a new material with nodes and its Principled
/// BSDF node as `bsdf`.
std::string opening(const std::string& what, const std::string& name, const std::string& source,
                    const std::string& guard) {
  std::string s = what;
  s += "# Fitted to: " + python_string(source) + "\n";
  s += "# Run in Blender's Python console or: blender -b FILE.blend --python THIS.py\n";
  s += "import bpy\n\n";
  s += guard;
  s += "mat = bpy.data.materials.new(name=" + python_string(name) + ")\n";
  s += "mat.use_nodes = True\n";
  s += "nodes, links = mat.node_tree.nodes, mat.node_tree.links\n";
  s += "bsdf = next(n for n in nodes if n.type == 'BSDF_PRINCIPLED')\n";
  return s;
}

/// The script's end: the material given to the active mesh object, if there is one.
std::string assignment() {
  return "obj = bpy.context.active_object\n"
         "if obj is not None and obj.type == 'MESH':\n"
         "    obj.data.materials.clear()\n"
         "    obj.data.materials.append(mat)\n";
}

}  // namespace

std::string blender_snippet(const GltfPbr& m, const std::string& name, const std::string& source) {
  std::string s = opening("# Blender (2.8-4.x) Principled BSDF of a glTF metallic-roughness fit made by `matlas fit`.\n", name,
                          source,
                          "if bpy.app.version < (4, 0, 0):\n"
                          "    print('matlas: Blender before 4.0 has another Principled BSDF, so this glTF fit is approximate here; '\n"
                          "          '`matlas fit --model principled-v1` fits that BSDF itself')\n");
  s += "bsdf.inputs['Base Color'].default_value = " + colour(m.base_color) + "\n";
  s += "bsdf.inputs['Metallic'].default_value = " + number(m.metallic) + "\n";
  s += "bsdf.inputs['Roughness'].default_value = " + number(m.roughness) + "\n";
  s += "bsdf.inputs['IOR'].default_value = " + number(m.ior) + "\n";
  s += "if 'Specular IOR Level' in bsdf.inputs:  # Blender 4.x\n";
  s += "    bsdf.inputs['Specular IOR Level'].default_value = " + number(0.5 * m.specular) + "\n";
  s += "else:  # Blender 2.8-3.x: 0.5 is F0 = 0.04\n";
  s += "    bsdf.inputs['Specular'].default_value = " + number(0.5 * m.specular) + "\n";
  if (m.sheen_color.maxCoeff() > 0) {
    s += "if 'Sheen Weight' in bsdf.inputs:  # Blender 4.x: a microfibre sheen layer, as KHR_materials_sheen\n";
    s += "    bsdf.inputs['Sheen Weight'].default_value = 1.0\n";
    s += "    bsdf.inputs['Sheen Tint'].default_value = " + colour(m.sheen_color) + "\n";
    s += "    bsdf.inputs['Sheen Roughness'].default_value = " + number(m.sheen_roughness) + "\n";
    s += "else:  # Blender 2.8-3.x: Disney's sheen, another lobe; its weight only\n";
    s += "    bsdf.inputs['Sheen'].default_value = " + number(m.sheen_color.maxCoeff()) + "\n";
  }
  s += "if 'Coat Weight' in bsdf.inputs:  # Blender 4.x\n";
  s += "    bsdf.inputs['Coat Weight'].default_value = " + number(m.clearcoat) + "\n";
  s += "    bsdf.inputs['Coat Roughness'].default_value = " + number(m.clearcoat_roughness) + "\n";
  if (m.clearcoat > 0) {
    // Blender 2.8-3.x: its Clearcoat is Disney's (a GTR1 lobe at a quarter of the weight), far
    // from glTF's (bench/blender_check.sh): the coat is a GGX Glossy BSDF mixed over the base by
    // clearcoat x Fresnel(n.v, IOR 1.5), as the extension's reference code layers it.
    s += "else:  # Blender 2.8-3.x: a GGX coat layer (its Clearcoat is another lobe)\n";
    s += "    output = next(n for n in nodes if n.type == 'OUTPUT_MATERIAL')\n";
    s += "    coat = nodes.new('ShaderNodeBsdfGlossy')\n";
    s += "    coat.distribution = 'GGX'\n";
    s += "    coat.inputs['Roughness'].default_value = " + number(m.clearcoat_roughness) + "\n";
    s += "    fresnel = nodes.new('ShaderNodeFresnel')\n";
    s += "    fresnel.inputs['IOR'].default_value = 1.5\n";
    s += "    weight = nodes.new('ShaderNodeMath')\n";
    s += "    weight.operation = 'MULTIPLY'\n";
    s += "    weight.inputs[1].default_value = " + number(m.clearcoat) + "\n";
    s += "    mix = nodes.new('ShaderNodeMixShader')\n";
    s += "    links.new(fresnel.outputs['Fac'], weight.inputs[0])\n";
    s += "    links.new(weight.outputs['Value'], mix.inputs['Fac'])\n";
    s += "    links.new(bsdf.outputs['BSDF'], mix.inputs[1])\n";
    s += "    links.new(coat.outputs['BSDF'], mix.inputs[2])\n";
    s += "    links.new(mix.outputs['Shader'], output.inputs['Surface'])\n";
  }
  s += assignment();
  return s;
}

std::string blender_snippet(const PrincipledV1& m, const std::string& name, const std::string& source) {
  std::string s = opening(
      "# Blender 2.8-3.6 Principled BSDF fitted by `matlas fit --model principled-v1`: the parameters of\n"
      "# the BSDF itself (Cycles' Principled v1, GGX distribution), so that Cycles renders the fitted model;\n"
      "# a coat is a second Principled BSDF added over it (the Clearcoat input stays 0: Cycles 2.8-3.6\n"
      "# renders that lobe brighter than its BRDF).\n",
      name, source,
      "if bpy.app.version >= (4, 0, 0):\n"
      "    raise RuntimeError('this is a fit of the Principled BSDF of Blender 2.8-3.6, which Blender 4 replaced: '\n"
      "                       'for Blender 4 fit with `matlas fit --model gltf`')\n");
  s += "bsdf.distribution = 'GGX'  # as fitted: Multiscatter GGX adds energy to rough lobes\n";
  s += "bsdf.inputs['Base Color'].default_value = " + colour(m.base_color) + "\n";
  const std::pair<const char*, double> inputs[] = {
      {"Metallic", m.metallic},   {"Specular", m.specular},    {"Specular Tint", m.specular_tint},
      {"Roughness", m.roughness}, {"Sheen", m.sheen},          {"Sheen Tint", m.sheen_tint},
      {"Clearcoat", 0.0},         {"Subsurface", 0.0},         {"Transmission", 0.0},
      {"Anisotropic", 0.0}};
  for (const auto& [input, value] : inputs)
    s += "bsdf.inputs['" + std::string(input) + "'].default_value = " + number(value) + "\n";
  if (m.coat > 0) {
    s += "# The coat: a black dielectric Principled BSDF (Specular 0.5: F0 0.04, IOR 1.5), mixed in at its\n";
    s += "# weight (a Mix Shader with nothing on its other input) and added.\n";
    s += "output = next(n for n in nodes if n.type == 'OUTPUT_MATERIAL')\n";
    s += "coat = nodes.new('ShaderNodeBsdfPrincipled')\n";
    s += "coat.distribution = 'GGX'\n";
    s += "coat.inputs['Base Color'].default_value = (0.0, 0.0, 0.0, 1.0)\n";
    s += "coat.inputs['Specular'].default_value = 0.5\n";
    s += "coat.inputs['Roughness'].default_value = " + number(m.coat_roughness) + "\n";
    s += "weight = nodes.new('ShaderNodeMixShader')\n";
    s += "weight.inputs['Fac'].default_value = " + number(m.coat) + "\n";
    s += "links.new(coat.outputs['BSDF'], weight.inputs[2])\n";
    s += "layered = nodes.new('ShaderNodeAddShader')\n";
    s += "links.new(bsdf.outputs['BSDF'], layered.inputs[0])\n";
    s += "links.new(weight.outputs['Shader'], layered.inputs[1])\n";
    s += "links.new(layered.outputs['Shader'], output.inputs['Surface'])\n";
  }
  s += assignment();
  return s;
}

namespace {

void write_text(const std::filesystem::path& path, const std::string& text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

}  // namespace

void write_blender_snippet(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                           const std::string& source) {
  write_text(path, blender_snippet(model, name, source));
}

void write_blender_snippet(const std::filesystem::path& path, const PrincipledV1& model, const std::string& name,
                           const std::string& source) {
  write_text(path, blender_snippet(model, name, source));
}

}  // namespace matlas::artist
