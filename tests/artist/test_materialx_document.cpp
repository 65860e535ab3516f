// The MaterialX document of a fitted material, parsed back with pugixml: an open_pbr_surface node
// with the OpenPBR inputs (names, types, values), the surfacematerial that uses it, written
// atomically.
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include "artist/materialx_document.h"
#include "core/error.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

struct Input {
  std::string type, value;
};

/// The inputs of `node` by name.
std::map<std::string, Input> inputs_of(const pugi::xml_node& node) {
  std::map<std::string, Input> out;
  for (const pugi::xml_node& in : node.children("input"))
    out[in.attribute("name").value()] = {in.attribute("type").value(), in.attribute("value").value()};
  return out;
}

double as_float(const Input& in) { return std::stod(in.value); }

Rgb as_color(const Input& in) {
  Rgb c;
  char comma;
  std::istringstream s(in.value);
  s >> c[0] >> comma >> c[1] >> comma >> c[2];
  EXPECT_TRUE(s) << in.value;
  return c;
}

TEST(MaterialxDocument, PugixmlReadsAnOpenPbrSurfaceAndItsMaterial) {
  GltfPbr m{Rgb(0.8, 0.25, 0.125), 0.3, 0.45, 0.6, 1.7, 0.5, 0.1};
  m.sheen_color = Rgb(0.4, 0.3, 0.2);
  m.sheen_roughness = 0.35;
  const test::TempDir dir("matlas-materialx");
  const fs::path path = dir / "red.mtlx";
  artist::write_materialx_document(path, m, "red \"paint\" é", "red <1>.binary");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1);  // no temporary left

  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_file(path.c_str());
  ASSERT_TRUE(parsed) << parsed.description();
  const pugi::xml_node root = doc.child("materialx");
  ASSERT_TRUE(root);
  EXPECT_STREQ(root.attribute("version").value(), "1.39");

  const pugi::xml_node shader = root.child("open_pbr_surface");
  ASSERT_TRUE(shader);
  EXPECT_STREQ(shader.attribute("type").value(), "surfaceshader");
  EXPECT_STREQ(shader.attribute("name").value(), "SR_red__paint____");  // é is two bytes
  EXPECT_STREQ(shader.attribute("doc").value(), "matlas fit of red <1>.binary");
  const auto in = inputs_of(shader);
  const std::map<std::string, std::string> types = {
      {"base_weight", "float"},      {"base_color", "color3"},         {"base_metalness", "float"},
      {"base_diffuse_roughness", "float"}, {"specular_weight", "float"}, {"specular_color", "color3"},
      {"specular_roughness", "float"}, {"specular_ior", "float"},      {"coat_weight", "float"},
      {"coat_roughness", "float"},   {"coat_ior", "float"},            {"coat_darkening", "float"},
      {"fuzz_weight", "float"},      {"fuzz_color", "color3"},         {"fuzz_roughness", "float"}};
  EXPECT_EQ(in.size(), types.size());
  for (const auto& [name, type] : types) {
    ASSERT_EQ(in.count(name), 1u) << name;
    EXPECT_EQ(in.at(name).type, type) << name;
  }
  // The parameters come back (six significant digits: within 5e-6 relative).
  const Rgb base = as_color(in.at("base_color"));
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(base[c], m.base_color[c]);
  EXPECT_DOUBLE_EQ(as_float(in.at("base_metalness")), m.metallic);
  EXPECT_DOUBLE_EQ(as_float(in.at("specular_roughness")), m.roughness);
  EXPECT_DOUBLE_EQ(as_float(in.at("specular_weight")), m.specular);
  EXPECT_DOUBLE_EQ(as_float(in.at("specular_ior")), m.ior);
  EXPECT_DOUBLE_EQ(as_float(in.at("coat_weight")), m.clearcoat);
  EXPECT_DOUBLE_EQ(as_float(in.at("coat_roughness")), m.clearcoat_roughness);
  EXPECT_DOUBLE_EQ(as_float(in.at("coat_ior")), 1.5);
  EXPECT_DOUBLE_EQ(as_float(in.at("coat_darkening")), 0.0);
  EXPECT_TRUE((as_color(in.at("specular_color")) == 1.0).all());
  // The sheen as OpenPBR's fuzz.
  EXPECT_DOUBLE_EQ(as_float(in.at("fuzz_weight")), 1.0);
  const Rgb fuzz = as_color(in.at("fuzz_color"));
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(fuzz[c], m.sheen_color[c]);
  EXPECT_DOUBLE_EQ(as_float(in.at("fuzz_roughness")), m.sheen_roughness);

  const pugi::xml_node material = root.child("surfacematerial");
  ASSERT_TRUE(material);
  EXPECT_STREQ(material.attribute("type").value(), "material");
  EXPECT_STREQ(material.attribute("name").value(), "red__paint____");
  EXPECT_STREQ(material.attribute("doc").value(), "red \"paint\" é");
  const pugi::xml_node surface = material.find_child_by_attribute("input", "name", "surfaceshader");
  ASSERT_TRUE(surface);
  EXPECT_STREQ(surface.attribute("type").value(), "surfaceshader");
  EXPECT_STREQ(surface.attribute("nodename").value(), shader.attribute("name").value());
}

TEST(MaterialxDocument, RoundTripsFittedParametersToSixSignificantDigits) {
  const GltfPbr m{Rgb(0.123456789, 0.0004321987, 0.999999), 0.987654321, 0.0314159265, 0.2718281828, 1.45,
                  0.0, 0.0};
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(artist::materialx_document(m, "x", "y").c_str()));
  const auto in = inputs_of(doc.child("materialx").child("open_pbr_surface"));
  const Rgb base = as_color(in.at("base_color"));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(base[c], m.base_color[c], 5e-6 * m.base_color[c]);
  EXPECT_NEAR(as_float(in.at("base_metalness")), m.metallic, 1e-6);
  EXPECT_NEAR(as_float(in.at("specular_roughness")), m.roughness, 1e-7);
  EXPECT_NEAR(as_float(in.at("specular_weight")), m.specular, 1e-6);
  EXPECT_DOUBLE_EQ(as_float(in.at("specular_ior")), 1.45);
}

TEST(MaterialxDocument, NamesAreMaterialxIdentifiersAndBadUtf8IsReplaced) {
  EXPECT_EQ(artist::materialx_identifier("gray-plastic"), "gray_plastic");
  EXPECT_EQ(artist::materialx_identifier("3M tape"), "M_3M_tape");
  EXPECT_EQ(artist::materialx_identifier(""), "M_");
  const std::string text = artist::materialx_document(GltfPbr{}, "bad \xff\xfe name", "a\x01z");
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(text.c_str())) << text;
  EXPECT_STREQ(doc.child("materialx").child("surfacematerial").attribute("doc").value(), "bad ?? name");
  EXPECT_STREQ(doc.child("materialx").child("open_pbr_surface").attribute("doc").value(), "matlas fit of a?z");
}

TEST(MaterialxDocument, AnUnwritableTargetIsNamedInTheError) {
  const test::TempDir dir("matlas-materialx");
  try {
    artist::write_materialx_document(dir / "missing-folder" / "a.mtlx", GltfPbr{}, "a", "b");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.mtlx"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace matlas
