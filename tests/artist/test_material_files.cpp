// The fitted material's files: a glTF 2.0 document read back by tinygltf (as glTF tools read it)
// and a Blender script that Python parses, both written atomically.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "artist/blender_snippet.h"
#include "artist/gltf_material.h"
#include "core/error.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

const GltfPbr kMaterial{Rgb(0.8, 0.25, 0.125), 0.3, 0.45, 0.6, 1.5};

[[maybe_unused]] std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(GltfMaterial, TinyGltfReadsTheMaterialWithItsSpecularExtension) {
  const test::TempDir dir("matlas-gltf-material");
  const fs::path path = dir / "red.gltf";
  artist::write_gltf_material(path, kMaterial, "red \"paint\" é", "red.binary");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1);  // no temporary left

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, path.string())) << err;
  EXPECT_EQ(model.asset.version, "2.0");
  ASSERT_EQ(model.materials.size(), 1u);
  const tinygltf::Material& m = model.materials[0];
  EXPECT_EQ(m.name, "red \"paint\" é");
  ASSERT_EQ(m.pbrMetallicRoughness.baseColorFactor.size(), 4u);
  EXPECT_DOUBLE_EQ(m.pbrMetallicRoughness.baseColorFactor[0], 0.8);
  EXPECT_DOUBLE_EQ(m.pbrMetallicRoughness.baseColorFactor[2], 0.125);
  EXPECT_DOUBLE_EQ(m.pbrMetallicRoughness.baseColorFactor[3], 1.0);
  EXPECT_DOUBLE_EQ(m.pbrMetallicRoughness.metallicFactor, 0.3);
  EXPECT_DOUBLE_EQ(m.pbrMetallicRoughness.roughnessFactor, 0.45);
  ASSERT_EQ(m.extensions.count("KHR_materials_specular"), 1u);
  EXPECT_DOUBLE_EQ(m.extensions.at("KHR_materials_specular").Get("specularFactor").GetNumberAsDouble(), 0.6);
  EXPECT_EQ(m.extensions.count("KHR_materials_ior"), 0u);  // 1.5 is the core specification's
  ASSERT_EQ(model.extensionsUsed.size(), 1u);
  EXPECT_EQ(model.extensionsUsed[0], "KHR_materials_specular");
}

TEST(GltfMaterial, AnotherIorIsWrittenWithItsExtension) {
  GltfPbr m = kMaterial;
  m.ior = 1.7;
  const nlohmann::json doc = nlohmann::json::parse(artist::gltf_material_document(m, "x", "y"));
  EXPECT_DOUBLE_EQ(doc["materials"][0]["extensions"]["KHR_materials_ior"]["ior"].get<double>(), 1.7);
  EXPECT_EQ(doc["extensionsUsed"].size(), 2u);
  EXPECT_EQ(doc["materials"][0]["extras"]["matlas_fit_of"], "y");
}

TEST(GltfMaterial, ASheenIsWrittenWithItsExtensionAndReadByTinyGltf) {
  GltfPbr m = kMaterial;
  m.sheen_color = Rgb::Constant(0.625);
  m.sheen_roughness = 0.375;
  const test::TempDir dir("matlas-gltf-sheen");
  const fs::path path = dir / "velvet.gltf";
  artist::write_gltf_material(path, m, "velvet", "v.binary");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, path.string())) << err;
  ASSERT_EQ(model.materials.size(), 1u);
  const auto& ext = model.materials[0].extensions;
  ASSERT_EQ(ext.count("KHR_materials_sheen"), 1u);
  const tinygltf::Value& sheen = ext.at("KHR_materials_sheen");
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(sheen.Get("sheenColorFactor").Get(c).GetNumberAsDouble(), 0.625);
  EXPECT_DOUBLE_EQ(sheen.Get("sheenRoughnessFactor").GetNumberAsDouble(), 0.375);
  EXPECT_NE(std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), "KHR_materials_sheen"),
            model.extensionsUsed.end());
  // Without a sheen, no extension.
  const nlohmann::json plain = nlohmann::json::parse(artist::gltf_material_document(kMaterial, "x", "y"));
  EXPECT_FALSE(plain["materials"][0]["extensions"].contains("KHR_materials_sheen"));
}

TEST(GltfMaterial, AnUnwritableTargetIsNamedInTheError) {
  const test::TempDir dir("matlas-gltf-material");
  const fs::path path = dir / "missing-folder" / "a.gltf";
  try {
    artist::write_gltf_material(path, kMaterial, "a", "b");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.gltf"), std::string::npos) << e.what();
  }
}

TEST(BlenderSnippet, SetsThePrincipledInputsForOldAndNewBlender) {
  const std::string s = artist::blender_snippet(kMaterial, "red", "red.binary");
  EXPECT_NE(s.find("bsdf.inputs['Base Color'].default_value = (0.8, 0.25, 0.125, 1.0)"), std::string::npos) << s;
  EXPECT_NE(s.find("bsdf.inputs['Metallic'].default_value = 0.3\n"), std::string::npos) << s;
  EXPECT_NE(s.find("bsdf.inputs['Roughness'].default_value = 0.45\n"), std::string::npos) << s;
  EXPECT_NE(s.find("bsdf.inputs['Specular IOR Level'].default_value = 0.3\n"), std::string::npos) << s;
  EXPECT_NE(s.find("bsdf.inputs['Specular'].default_value = 0.3\n"), std::string::npos) << s;
}

TEST(BlenderSnippet, ACoatIsPrincipledCoatIn4xAndAGgxLayerBefore) {
  GltfPbr m = kMaterial;
  m.clearcoat = 0.25;
  m.clearcoat_roughness = 0.125;
  const std::string s = artist::blender_snippet(m, "coated", "c.binary");
  EXPECT_NE(s.find("    bsdf.inputs['Coat Weight'].default_value = 0.25\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    coat.distribution = 'GGX'\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    coat.inputs['Roughness'].default_value = 0.125\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    weight.inputs[1].default_value = 0.25\n"), std::string::npos) << s;
  EXPECT_EQ(s.find("'Clearcoat'"), std::string::npos) << s;  // Disney's lobe is not used
  // Without a coat, no layer.
  EXPECT_EQ(artist::blender_snippet(kMaterial, "plain", "p.binary").find("ShaderNodeBsdfGlossy"), std::string::npos);
}

TEST(BlenderSnippet, ASheenIsPrincipledSheenIn4xAndItsWeightBefore) {
  GltfPbr m = kMaterial;
  m.sheen_color = Rgb(0.5, 0.25, 0.125);
  m.sheen_roughness = 0.375;
  const std::string s = artist::blender_snippet(m, "velvet", "v.binary");
  EXPECT_NE(s.find("    bsdf.inputs['Sheen Weight'].default_value = 1.0\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    bsdf.inputs['Sheen Tint'].default_value = (0.5, 0.25, 0.125, 1.0)\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    bsdf.inputs['Sheen Roughness'].default_value = 0.375\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    bsdf.inputs['Sheen'].default_value = 0.5\n"), std::string::npos) << s;
  EXPECT_EQ(artist::blender_snippet(kMaterial, "plain", "p.binary").find("Sheen"), std::string::npos);
}

TEST(BlenderSnippet, IsValidPythonWhateverTheName) {
#ifndef MATLAS_PYTHON3
  GTEST_SKIP() << "no python3";
#else
  const test::TempDir dir("matlas-blender-snippet");
  const fs::path path = dir / "m.py";
  GltfPbr coated = kMaterial;
  coated.clearcoat = 0.5;  // the coat layer's lines too
  artist::write_blender_snippet(path, coated, "quote ' \" back\\slash\nnew line é", "a\nb.binary");
  const std::string command = std::string(MATLAS_PYTHON3) + " -c \"import ast, sys; ast.parse(open(sys.argv[1], encoding='utf-8').read())\" '" +
                              path.string() + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << read_text(path);
#endif
}

}  // namespace
}  // namespace matlas
