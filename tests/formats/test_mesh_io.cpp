// Mesh files: OBJ (polygons, negative indices, normals) and glTF binaries (node transforms,
// 16-bit indices), round trips and errors. The installed Draco-compressed bunny if present.
#include <gtest/gtest.h>

#include <cstring>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/mesh_io.h"
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

/// A .glb with one quad (4 float positions, 6 uint16 indices) under a node with a translation
/// and a uniform scale.
std::string quad_glb() {
  const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  while (bin.size() % 4) bin.push_back('\0');
  const nlohmann::json gltf = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                      {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
                     {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"nodes", {{{"mesh", 0}, {"translation", {0, 0, 5}}, {"scale", {2, 2, 2}}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
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
