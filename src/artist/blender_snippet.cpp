#include "artist/blender_snippet.h"

#include <cstdio>

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

}  // namespace

std::string blender_snippet(const GltfPbr& m, const std::string& name, const std::string& source) {
  char base[96];
  std::snprintf(base, sizeof base, "(%.6g, %.6g, %.6g, 1.0)", m.base_color[0], m.base_color[1], m.base_color[2]);
  std::string s;
  s += "# Blender (2.8-4.x) Principled BSDF of a glTF metallic-roughness fit made by `matlas fit`.\n";
  s += "# Fitted to: " + python_string(source) + "\n";
  s += "# Run in Blender's Python console or: blender -b FILE.blend --python THIS.py\n";
  s += "import bpy\n\n";
  s += "mat = bpy.data.materials.new(name=" + python_string(name) + ")\n";
  s += "mat.use_nodes = True\n";
  s += "bsdf = next(n for n in mat.node_tree.nodes if n.type == 'BSDF_PRINCIPLED')\n";
  s += "bsdf.inputs['Base Color'].default_value = " + std::string(base) + "\n";
  s += "bsdf.inputs['Metallic'].default_value = " + number(m.metallic) + "\n";
  s += "bsdf.inputs['Roughness'].default_value = " + number(m.roughness) + "\n";
  s += "bsdf.inputs['IOR'].default_value = " + number(m.ior) + "\n";
  s += "if 'Specular IOR Level' in bsdf.inputs:  # Blender 4.x\n";
  s += "    bsdf.inputs['Specular IOR Level'].default_value = " + number(0.5 * m.specular) + "\n";
  s += "else:  # Blender 2.8-3.x: 0.5 is F0 = 0.04\n";
  s += "    bsdf.inputs['Specular'].default_value = " + number(0.5 * m.specular) + "\n";
  if (m.sheen_color.maxCoeff() > 0) {
    char tint[96];
    std::snprintf(tint, sizeof tint, "(%.6g, %.6g, %.6g, 1.0)", m.sheen_color[0], m.sheen_color[1], m.sheen_color[2]);
    s += "if 'Sheen Weight' in bsdf.inputs:  # Blender 4.x: a microfibre sheen layer, as KHR_materials_sheen\n";
    s += "    bsdf.inputs['Sheen Weight'].default_value = 1.0\n";
    s += "    bsdf.inputs['Sheen Tint'].default_value = " + std::string(tint) + "\n";
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
    s += "    nodes, links = mat.node_tree.nodes, mat.node_tree.links\n";
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
  s += "obj = bpy.context.active_object\n";
  s += "if obj is not None and obj.type == 'MESH':\n";
  s += "    obj.data.materials.clear()\n";
  s += "    obj.data.materials.append(mat)\n";
  return s;
}

void write_blender_snippet(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                           const std::string& source) {
  AtomicFile file(path);
  file.write(blender_snippet(model, name, source));
  file.commit();
}

}  // namespace matlas::artist
