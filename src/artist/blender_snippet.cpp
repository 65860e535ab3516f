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
  s += "if 'Coat Weight' in bsdf.inputs:  # Blender 4.x\n";
  s += "    bsdf.inputs['Coat Weight'].default_value = " + number(m.clearcoat) + "\n";
  s += "    bsdf.inputs['Coat Roughness'].default_value = " + number(m.clearcoat_roughness) + "\n";
  s += "else:\n";
  s += "    bsdf.inputs['Clearcoat'].default_value = " + number(m.clearcoat) + "\n";
  s += "    bsdf.inputs['Clearcoat Roughness'].default_value = " + number(m.clearcoat_roughness) + "\n";
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
