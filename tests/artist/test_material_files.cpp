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
  // Before 4.0 the script says that the fit is approximate there and what fits that BSDF itself.
  EXPECT_NE(s.find("if bpy.app.version < (4, 0, 0):\n    print('matlas: Blender before 4.0"), std::string::npos) << s;
  EXPECT_NE(s.find("--model principled-v1"), std::string::npos) << s;
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

/// Runs a Blender script against a stand-in `bpy` (a material's node tree with a Principled BSDF
/// and an output node, nodes.new and links.new, bpy.app.version as given) and returns the tree the
/// script built as JSON: {"nodes": [{"type", "distribution", "inputs": {name: value}}], "links":
/// [[from node, from socket, to node, to socket]]} (node indices, socket names or indices), or
/// {"error": message} if it raised.
[[maybe_unused]] nlohmann::json run_with_fake_bpy(const fs::path& dir, const fs::path& script, const std::string& version) {
  std::ofstream(dir / "bpy.py") << R"(import types
class Socket:
    def __init__(self, node, key): self.node, self.key, self.default_value = node, key, None
class Sockets(dict):
    def __init__(self, node): super().__init__(); self.node = node
    def __missing__(self, key):
        self[key] = Socket(self.node, key)
        return self[key]
TYPES = {'ShaderNodeBsdfPrincipled': 'BSDF_PRINCIPLED', 'ShaderNodeMixShader': 'MIX_SHADER',
         'ShaderNodeAddShader': 'ADD_SHADER', 'ShaderNodeOutputMaterial': 'OUTPUT_MATERIAL'}
class Node:
    def __init__(self, kind):
        self.type, self.distribution = TYPES[kind], None
        self.inputs, self.outputs = Sockets(self), Sockets(self)
class Nodes(list):
    def new(self, kind):
        self.append(Node(kind))
        return self[-1]
class Links(list):
    def new(self, a, b): self.append((a, b))
class Material:
    def __init__(self, name):
        self.name, self.use_nodes = name, False
        self.node_tree = types.SimpleNamespace(nodes=Nodes(), links=Links())
        self.node_tree.nodes.new('ShaderNodeBsdfPrincipled').distribution = 'MULTI_GGX'
        self.node_tree.nodes.new('ShaderNodeOutputMaterial')
made = []
def new(name):
    made.append(Material(name))
    return made[-1]
app = types.SimpleNamespace(version=tuple(int(v) for v in open('version').read().split('.')))
data = types.SimpleNamespace(materials=types.SimpleNamespace(new=new))
context = types.SimpleNamespace(active_object=None)
)";
  std::ofstream(dir / "version") << version;
  std::ofstream(dir / "run.py") << R"(import json, sys
sys.path.insert(0, '.')
import bpy
try:
    exec(open(sys.argv[1], encoding='utf-8').read(), {})
    tree = bpy.made[0].node_tree
    index = {id(n): k for k, n in enumerate(tree.nodes)}
    out = {'nodes': [{'type': n.type, 'distribution': n.distribution,
                      'inputs': {str(k): v.default_value for k, v in n.inputs.items()}} for n in tree.nodes],
           'links': [[index[id(a.node)], a.key, index[id(b.node)], b.key] for a, b in tree.links]}
except RuntimeError as e:
    out = {'error': str(e)}
json.dump(out, open('out.json', 'w'))
)";
  const std::string command = "cd '" + dir.string() + "' && " + std::string(MATLAS_PYTHON3) + " run.py '" + script.string() + "'";
  if (std::system(command.c_str()) != 0) return {{"error", "the script failed to run"}};
  return nlohmann::json::parse(read_text(dir / "out.json"));
}

TEST(BlenderSnippet, APrincipledV1FitSetsTheBsdfsOwnInputsAddsTheCoatLayerAndRefusesBlender4) {
#ifndef MATLAS_PYTHON3
  GTEST_SKIP() << "no python3";
#else
  const test::TempDir dir("matlas-blender-v1");
  PrincipledV1 m;
  m.base_color = Rgb(0.5, 0.25, 0.125);
  m.metallic = 0.25;
  m.specular = 0.375;
  m.roughness = 0.3;
  m.sheen = 0.5;
  m.sheen_tint = 0.75;
  m.coat = 0.625;
  m.coat_roughness = 0.0625;
  const fs::path script = dir / "v1.py";
  artist::write_blender_snippet(script, m, "paint", "paint.binary");
  const nlohmann::json tree = run_with_fake_bpy(dir.path(), script, "3.4.1");
  ASSERT_FALSE(tree.contains("error")) << tree.dump();
  ASSERT_EQ(tree["nodes"].size(), 5u) << tree.dump();  // BSDF, output, coat BSDF, mix, add
  const nlohmann::json& bsdf = tree["nodes"][0];
  EXPECT_EQ(bsdf["distribution"], "GGX");
  const nlohmann::json& i = bsdf["inputs"];
  EXPECT_EQ(i["Base Color"], nlohmann::json({0.5, 0.25, 0.125, 1.0}));
  const std::pair<const char*, double> expected[] = {
      {"Metallic", 0.25}, {"Specular", 0.375}, {"Specular Tint", 0.0}, {"Roughness", 0.3}, {"Sheen", 0.5},
      {"Sheen Tint", 0.75}, {"Clearcoat", 0.0}, {"Subsurface", 0.0}, {"Transmission", 0.0}, {"Anisotropic", 0.0}};
  for (const auto& [name, value] : expected) EXPECT_DOUBLE_EQ(i[name].get<double>(), value) << name;
  // The coat: a black Principled BSDF of Specular 0.5 and the coat's roughness, through a Mix
  // Shader at the coat's weight (its first shader input left empty), added to the BSDF, into the
  // output's Surface.
  const nlohmann::json& coat = tree["nodes"][2];
  EXPECT_EQ(coat["type"], "BSDF_PRINCIPLED");
  EXPECT_EQ(coat["distribution"], "GGX");
  EXPECT_EQ(coat["inputs"]["Base Color"], nlohmann::json({0.0, 0.0, 0.0, 1.0}));
  EXPECT_DOUBLE_EQ(coat["inputs"]["Specular"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(coat["inputs"]["Roughness"].get<double>(), 0.0625);
  EXPECT_EQ(tree["nodes"][3]["type"], "MIX_SHADER");
  EXPECT_DOUBLE_EQ(tree["nodes"][3]["inputs"]["Fac"].get<double>(), 0.625);
  EXPECT_EQ(tree["nodes"][4]["type"], "ADD_SHADER");
  const nlohmann::json links = {{2, "BSDF", 3, 2}, {0, "BSDF", 4, 0}, {3, "Shader", 4, 1}, {4, "Shader", 1, "Surface"}};
  EXPECT_EQ(tree["links"], links) << tree.dump();
  // Without a coat the BSDF goes to the output as it is.
  m.coat = 0.0;
  artist::write_blender_snippet(script, m, "paint", "paint.binary");
  EXPECT_EQ(run_with_fake_bpy(dir.path(), script, "3.6.0")["nodes"].size(), 2u);

  const nlohmann::json in40 = run_with_fake_bpy(dir.path(), script, "4.0.0");
  ASSERT_TRUE(in40.contains("error")) << in40.dump();
  EXPECT_NE(in40["error"].get<std::string>().find("--model gltf"), std::string::npos) << in40.dump();
#endif
}

}  // namespace
}  // namespace matlas
