#include "artist/materialx_document.h"

#include <cstdio>
#include <sstream>

#include <pugixml.hpp>

#include "core/atomic_file.h"

namespace matlas::artist {

namespace {

/// Six significant digits, as the glTF document and the Blender script write them.
std::string mtlx_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// Text that XML can hold: bytes that are not valid UTF-8, and control characters other than tab
/// and newline, become '?'.
std::string xml_text(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = len > 0 && i + len <= s.size() && !(len == 1 && c < 0x20 && c != '\t' && c != '\n');
    for (std::size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(s[i + k]) >> 6) == 0x2;
    if (ok) {
      out.append(s, i, len);
      i += len;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

void add_input(pugi::xml_node node, const char* name, const char* type, const std::string& value) {
  pugi::xml_node input = node.append_child("input");
  input.append_attribute("name") = name;
  input.append_attribute("type") = type;
  input.append_attribute("value") = value.c_str();
}

void add_float(pugi::xml_node node, const char* name, double v) { add_input(node, name, "float", mtlx_number(v)); }

void add_color(pugi::xml_node node, const char* name, const Rgb& c) {
  add_input(node, name, "color3", mtlx_number(c[0]) + ", " + mtlx_number(c[1]) + ", " + mtlx_number(c[2]));
}

}  // namespace

std::string materialx_identifier(const std::string& name) {
  std::string id;
  for (const char c : name) {
    const bool word = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    id += word ? c : '_';
  }
  if (id.empty() || (id[0] >= '0' && id[0] <= '9')) id = "M_" + id;
  return id;
}

std::string materialx_document(const GltfPbr& m, const std::string& name, const std::string& source) {
  const std::string id = materialx_identifier(name);
  const std::string shader_name = "SR_" + id;
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child("materialx");
  root.append_attribute("version") = "1.39";
  root.append_attribute("colorspace") = "lin_rec709";
  root.append_child(pugi::node_comment)
      .set_value(" A glTF metallic-roughness fit made by `matlas fit`, as OpenPBR Surface (docs/EXPORT.md) ");

  pugi::xml_node shader = root.append_child("open_pbr_surface");
  shader.append_attribute("name") = shader_name.c_str();
  shader.append_attribute("type") = "surfaceshader";
  shader.append_attribute("doc") = xml_text("matlas fit of " + source).c_str();
  add_float(shader, "base_weight", 1.0);
  add_color(shader, "base_color", m.base_color);
  add_float(shader, "base_metalness", m.metallic);
  add_float(shader, "base_diffuse_roughness", 0.0);
  add_float(shader, "specular_weight", m.specular);
  add_color(shader, "specular_color", Rgb::Ones());
  add_float(shader, "specular_roughness", m.roughness);
  add_float(shader, "specular_ior", m.ior);
  add_float(shader, "coat_weight", m.clearcoat);
  add_float(shader, "coat_roughness", m.clearcoat_roughness);
  add_float(shader, "coat_ior", 1.5);
  add_float(shader, "coat_darkening", 0.0);
  // The sheen as OpenPBR's fuzz (a layer of fibres over the base, its colour and roughness).
  const double fuzz = m.sheen_color.maxCoeff();
  add_float(shader, "fuzz_weight", fuzz > 0 ? 1.0 : 0.0);
  add_color(shader, "fuzz_color", fuzz > 0 ? Rgb(m.sheen_color) : Rgb::Ones());
  add_float(shader, "fuzz_roughness", m.sheen_roughness);

  pugi::xml_node material = root.append_child("surfacematerial");
  material.append_attribute("name") = id.c_str();
  material.append_attribute("type") = "material";
  material.append_attribute("doc") = xml_text(name).c_str();
  pugi::xml_node input = material.append_child("input");
  input.append_attribute("name") = "surfaceshader";
  input.append_attribute("type") = "surfaceshader";
  input.append_attribute("nodename") = shader_name.c_str();

  std::ostringstream out;
  doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
  return out.str();
}

void write_materialx_document(const std::filesystem::path& path, const GltfPbr& model, const std::string& name,
                              const std::string& source) {
  AtomicFile file(path);
  file.write(materialx_document(model, name, source));
  file.commit();
}

}  // namespace matlas::artist
