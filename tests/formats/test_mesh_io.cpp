// Mesh files: OBJ (polygons, negative indices, normals) and glTF binaries (node transforms,
// 16-bit indices), round trips and errors. The installed Draco-compressed bunny if present.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <cstring>

#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/mesh_io.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

TEST(MeshIo, ObjPolygonsAreFannedAndNegativeIndicesResolved) {
  test::TempDir dir;
  write_file_atomic(dir / "q.obj", std::string("# quad and triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                               "f 1 2 3 4\nv 0 0 1\nf -1 1/7 2//3\n"));
  const TriangleMesh m = read_obj(dir / "q.obj");
  EXPECT_EQ(m.vertex_count(), 5u);
  ASSERT_EQ(m.triangle_count(), 3u);
  EXPECT_EQ((m.triangles[1]), (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ((m.triangles[2]), (std::array<std::uint32_t, 3>{4, 0, 1}));
  ASSERT_EQ(m.normals.size(), 5u);  // computed
  EXPECT_NEAR(m.normals[2].z(), 1.0f, 1e-6);
  const auto [lo, hi] = m.bounds();
  EXPECT_EQ(hi, Eigen::Vector3f(1, 1, 1));
  EXPECT_EQ(lo, Eigen::Vector3f(0, 0, 0));
}

TEST(MeshIo, ComputedNormalsAreUnitForLargeCoordinates) {
  // Found by the mesh fuzz target: a vertex at 9.4e21 made the face normal overflow float, and
  // the computed normals came out zero.
  test::TempDir dir;
  write_file_atomic(dir / "big.obj", std::string("v 0 0 0\nv 1e22 0 0\nv 0 1e22 0\nv 1e-30 0 1\nf 1 2 3\nf 1 2 4\n"));
  const TriangleMesh m = read_obj(dir / "big.obj");
  ASSERT_EQ(m.normals.size(), 4u);
  EXPECT_TRUE(m.normals[2].isApprox(Eigen::Vector3f(0, 0, 1))) << m.normals[2].transpose();
  for (const auto& n : m.normals) EXPECT_NEAR(n.norm(), 1.0f, 1e-6f) << n.transpose();
}

TEST(MeshIo, ObjRoundTripKeepsNormals) {
  test::TempDir dir;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0.6f, 0.8f}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}};
  write_obj(dir / "t.obj", m);
  const TriangleMesh back = read_mesh(dir / "t.obj");
  ASSERT_EQ(back.vertex_count(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(back.positions[i].isApprox(m.positions[i]));
    EXPECT_TRUE(back.normals[i].isApprox(m.normals[i], 1e-6f));
  }
}

/// A .glb container of a glTF document and its binary chunk.
std::string glb_of(const nlohmann::json& gltf, std::string bin) {
  while (bin.size() % 4) bin.push_back('\0');
  std::string json = gltf.dump();
  while (json.size() % 4) json.push_back(' ');
  auto u32 = [](std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  std::string glb = "glTF";
  u32(glb, 2);
  u32(glb, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  u32(glb, static_cast<std::uint32_t>(json.size()));
  glb += "JSON";
  glb += json;
  u32(glb, static_cast<std::uint32_t>(bin.size()));
  glb.append("BIN\0", 4);
  glb += bin;
  return glb;
}

/// The binary chunk of quad_gltf: 4 float positions, then 6 uint16 indices.
std::string quad_bin() {
  const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  while (bin.size() % 4) bin.push_back('\0');
  return bin;
}

/// A glTF document with one quad (accessor 0: positions, 1: indices) under a node with a
/// translation and a uniform scale.
nlohmann::json quad_gltf() {
  return {{"asset", {{"version", "2.0"}}},
          {"buffers", {{{"byteLength", quad_bin().size()}}}},
          {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                           {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
          {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                          {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
                         {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
          {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
          {"nodes", {{{"mesh", 0}, {"translation", {0, 0, 5}}, {"scale", {2, 2, 2}}}}},
          {"scenes", {{{"nodes", {0}}}}},
          {"scene", 0}};
}

std::string quad_glb() { return glb_of(quad_gltf(), quad_bin()); }

TEST(MeshIo, GlbPrimitivesAreReadWithTheirNodeTransforms) {
  test::TempDir dir;
  write_file_atomic(dir / "q.glb", quad_glb());
  const TriangleMesh m = read_mesh(dir / "q.glb");
  ASSERT_EQ(m.vertex_count(), 4u);
  ASSERT_EQ(m.triangle_count(), 2u);
  EXPECT_TRUE(m.positions[2].isApprox(Eigen::Vector3f(2, 2, 5)));
  EXPECT_EQ((m.triangles[1]), (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_NEAR(m.normals[0].z(), 1.0f, 1e-6);
  const std::string bytes = quad_glb();
  EXPECT_EQ(read_glb_memory(bytes.data(), bytes.size(), "memory").triangle_count(), 2u);
}

TEST(MeshIo, ErrorsNameTheFile) {
  test::TempDir dir;
  write_file_atomic(dir / "bad.obj", std::string("v 0 0 0\nf 1 2 3\n"));
  write_file_atomic(dir / "empty.obj", std::string("# nothing\n"));
  write_file_atomic(dir / "bad.glb", std::string("glTF garbage"));
  for (const std::string name : {"bad.obj", "empty.obj", "bad.glb", "missing.obj", "x.ply"}) {
    try {
      read_mesh(dir / name);
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

/// The error of reading a .glb made of `gltf` and the quad's binary chunk.
std::string glb_error(const nlohmann::json& gltf) {
  const std::string bytes = glb_of(gltf, quad_bin());
  return test::error_of([&] { read_glb_memory(bytes.data(), bytes.size(), "crafted.glb"); });
}

TEST(MeshIo, AccessorCountsThatWrapTheBoundsCheckAreRefused) {
  // (2^64 + 2) / 3 elements of 12 bytes: (count - 1) * 12 + 12 wraps around to 8 bytes, and the
  // allocation count * 3 to 2 floats; the loop then wrote count elements (heap overflow).
  const std::uint64_t wrapping = 6148914691236517206ull;
  nlohmann::json gltf = quad_gltf();
  gltf["accessors"][0]["count"] = wrapping;
  std::string e = glb_error(gltf);
  EXPECT_NE(e.find("crafted.glb: accessor 0 ("), std::string::npos) << e;
  EXPECT_NE(e.find("runs past its buffer view (48 bytes)"), std::string::npos) << e;
  // The same for the index accessor (2-byte elements: a count of 2^63 wraps).
  gltf = quad_gltf();
  gltf["accessors"][1]["count"] = std::uint64_t{1} << 63;
  e = glb_error(gltf);
  EXPECT_NE(e.find("crafted.glb: index accessor 1 ("), std::string::npos) << e;
  // One element too many, and offsets past the view or the buffer.
  gltf = quad_gltf();
  gltf["accessors"][0]["count"] = 5;
  EXPECT_NE(glb_error(gltf).find("accessor 0 (5 elements of 12 bytes"), std::string::npos) << glb_error(gltf);
  gltf = quad_gltf();
  gltf["accessors"][0]["byteOffset"] = std::uint64_t{1} << 62;
  EXPECT_NE(glb_error(gltf).find("runs past its buffer view"), std::string::npos) << glb_error(gltf);
  gltf = quad_gltf();
  gltf["bufferViews"][1]["byteOffset"] = 0xfffffffffffffff0ull;
  EXPECT_NE(glb_error(gltf).find("buffer view 1 (12 bytes at offset 18446744073709551600) runs past its buffer"),
            std::string::npos)
      << glb_error(gltf);
}

TEST(MeshIo, ReferencesToMissingObjectsAreErrorsNamingTheFile) {
  // Each used to be std::out_of_range from vector::at, or no check at all.
  const std::vector<std::pair<std::function<void(nlohmann::json&)>, std::string>> cases = {
      {[](nlohmann::json& g) { g["meshes"][0]["primitives"][0]["indices"] = 7; }, "refers to accessor 7"},
      {[](nlohmann::json& g) { g["accessors"][1]["bufferView"] = 9; }, "refers to buffer view 9"},
      {[](nlohmann::json& g) { g["bufferViews"][0]["buffer"] = 3; }, "refers to buffer 3"},
      {[](nlohmann::json& g) { g["nodes"][0]["mesh"] = 4; }, "refers to mesh 4"},
      {[](nlohmann::json& g) { g["scene"] = 2; }, "refers to scene 2"},
  };
  for (const auto& [edit, expected] : cases) {
    nlohmann::json gltf = quad_gltf();
    edit(gltf);
    const std::string e = glb_error(gltf);
    // tinygltf itself refuses some of these; either way a matlas::Error naming the file.
    EXPECT_EQ(e.rfind("crafted.glb: ", 0), 0u) << e;
    EXPECT_TRUE(e.find(expected) != std::string::npos || e.find("cannot read glTF binary") != std::string::npos) << e;
  }
}

TEST(MeshIo, SharedChildrenAndCyclesDoNotHang) {
  // 41 nodes, each listing the next twice: 2^40 paths to the last one, which holds the quad. Used
  // to run for many hours; now refused after kMaxGltfInstances visits.
  nlohmann::json gltf = quad_gltf();
  gltf["nodes"] = nlohmann::json::array();
  for (int i = 0; i < 40; ++i) gltf["nodes"].push_back({{"children", {i + 1, i + 1}}});
  gltf["nodes"].push_back({{"mesh", 0}});
  const auto start = std::chrono::steady_clock::now();
  std::string e = glb_error(gltf);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  EXPECT_NE(e.find("crafted.glb: the node graph instances more than 65536 nodes and primitives"), std::string::npos)
      << e;
  // A cycle (node 1 is its own grandchild) is refused as such (tinygltf 2.7 accepts it).
  gltf["nodes"] = {{{"children", {1}}}, {{"children", {2}}, {"mesh", 0}}, {{"children", {1}}}};
  e = glb_error(gltf);
  EXPECT_TRUE(e.find("crafted.glb: node 1 is its own ancestor (a cycle)") != std::string::npos ||
              e.find("crafted.glb: cannot read glTF binary") != std::string::npos)
      << e;
  // Sharing within the limits is fine: 2^6 instances of the quad.
  gltf["nodes"] = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) gltf["nodes"].push_back({{"children", {i + 1, i + 1}}});
  gltf["nodes"].push_back({{"mesh", 0}});
  const std::string bytes = glb_of(gltf, quad_bin());
  EXPECT_EQ(read_glb_memory(bytes.data(), bytes.size(), "shared.glb").triangle_count(), 2u * 64u);
}

TEST(MeshIo, DeeplyNestedJsonIsRefusedBeforeTinygltfRecursesIntoIt) {
  // tinygltf turns "extras" into its own values with a stack frame per level: 100000 nested
  // arrays overflowed the stack (a crash, not an error).
  const std::string deep = "{\"asset\": {\"version\": \"2.0\", \"extras\": " + std::string(100000, '[') +
                           std::string(100000, ']') + "}}";
  test::TempDir dir;
  write_file_atomic(dir / "deep.gltf", deep);
  std::string e = test::error_of([&] { read_mesh(dir / "deep.gltf"); });
  EXPECT_NE(e.find("deep.gltf: glTF JSON nested deeper than 256 levels"), std::string::npos) << e.substr(0, 300);
  std::string glb = quad_glb();
  const std::string bytes = glb.substr(0, 12) + [&] {
    std::string chunk;
    std::string json = deep;
    while (json.size() % 4) json.push_back(' ');
    const auto length = static_cast<std::uint32_t>(json.size());
    chunk.append(reinterpret_cast<const char*>(&length), 4);
    return chunk + "JSON" + json;
  }();
  e = test::error_of([&] { read_glb_memory(bytes.data(), bytes.size(), "deep.glb"); });
  EXPECT_NE(e.find("deep.glb: glTF JSON nested deeper than 256 levels"), std::string::npos) << e.substr(0, 300);
  // Brackets inside strings do not count.
  nlohmann::json gltf = quad_gltf();
  gltf["asset"]["extras"] = std::string(1000, '[');
  const std::string ok = glb_of(gltf, quad_bin());
  EXPECT_EQ(read_glb_memory(ok.data(), ok.size(), "ok.glb").triangle_count(), 2u);
}

TEST(MeshIo, ExternalBuffersAreReadAsRegularFilesOnly) {
  test::TempDir dir;
  nlohmann::json gltf = quad_gltf();
  gltf["buffers"][0]["uri"] = "quad.bin";
  write_file_atomic(dir / "quad.bin", quad_bin());
  write_file_atomic(dir / "quad.gltf", gltf.dump());
  EXPECT_EQ(read_mesh(dir / "quad.gltf").triangle_count(), 2u);
  // A FIFO in the buffer's place is refused instead of blocking the reader.
  std::filesystem::remove(dir / "quad.bin");
  ASSERT_EQ(::mkfifo((dir / "quad.bin").c_str(), 0600), 0);
  const std::string e = test::error_of([&] { read_mesh(dir / "quad.gltf"); });
  EXPECT_NE(e.find("quad.gltf: cannot read glTF"), std::string::npos) << e;
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
}

TEST(MeshIo, InstalledDracoBunnyDecodes) {
  std::filesystem::path path = "assets/models/bunny.glb";
  if (const char* env = std::getenv("MATLAS_ASSETS")) path = std::filesystem::path(env) / "models/bunny.glb";
  if (!std::filesystem::exists(path)) path = std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "assets/models/bunny.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "assets not installed (scripts/install-assets.sh)";
  const TriangleMesh m = read_mesh(path);
  EXPECT_GT(m.triangle_count(), 1000u);
  EXPECT_EQ(m.normals.size(), m.positions.size());
}

}  // namespace
}  // namespace matlas
