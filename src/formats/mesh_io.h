#pragma once
// Triangle meshes and their files: Wavefront OBJ (v / vn / f, polygons fanned into triangles,
// negative indices) and glTF 2.0 (.glb binary or .gltf with embedded/external buffers; every
// triangle primitive of the default scene with its node transforms; KHR_draco_mesh_compression
// decoded with Draco, as in the meshes of @pmndrs/assets).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace matlas {

/// An indexed triangle mesh in single precision (what the ray tracer consumes).
struct TriangleMesh {
  std::vector<Eigen::Vector3f> positions;
  /// Per-vertex shading normals (unit), same length as positions, or empty.
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  /// Axis-aligned bounding box (min, max); throws matlas::Error for an empty mesh.
  std::array<Eigen::Vector3f, 2> bounds() const;
  /// Replaces the normals by area-weighted averages of the face normals.
  void compute_normals();
  /// Appends another mesh (indices offset); normals are kept only if both have them.
  void append(const TriangleMesh& other);
};

/// The largest meshes read: beyond, a file is refused (a few hundred bytes of glTF can instance
/// one primitive many times over, and every instance is copied into the flattened mesh). About
/// 1.2 GB of positions, normals and triangles at the limit.
inline constexpr std::size_t kMaxMeshVertices = std::size_t{1} << 25;
inline constexpr std::size_t kMaxMeshTriangles = std::size_t{1} << 25;
/// glTF node graphs: at most this many node visits and primitive instances in all (a graph whose
/// nodes list the same child several times doubles at every level: 41 nodes can mean 2^40
/// visits), and a node that is its own ancestor (a cycle) is refused.
inline constexpr std::size_t kMaxGltfInstances = std::size_t{1} << 16;
/// The largest external glTF buffer (a .bin beside a .gltf) read.
inline constexpr std::uint64_t kMaxGltfBufferBytes = std::uint64_t{1} << 30;

/// Reads `.obj`, `.glb` or `.gltf` by extension. Throws matlas::Error naming the file if it is
/// missing, malformed, has no triangles, indexes out of range, refers to data outside its
/// buffers, or is beyond the limits above. Missing normals are computed.
TriangleMesh read_mesh(const std::filesystem::path& path);
TriangleMesh read_obj(const std::filesystem::path& path);
TriangleMesh read_gltf(const std::filesystem::path& path);
/// A `.glb` file held in memory; `name` appears in error messages.
TriangleMesh read_glb_memory(const void* data, std::size_t bytes, const std::string& name);

/// What every reader does last: refuses a mesh without triangles, beyond the limits, with indices
/// out of range or non-finite positions (matlas::Error naming `name`); normalises the normals,
/// computing them when missing or unusable.
void check_mesh(TriangleMesh& mesh, const std::string& name);
/// Refuses (matlas::Error naming `name`) more vertices or triangles than the limits above.
void check_mesh_size(std::size_t vertices, std::size_t triangles, const std::string& name);

/// Writes an OBJ file (positions, normals if present, faces) atomically.
void write_obj(const std::filesystem::path& path, const TriangleMesh& mesh);

}  // namespace matlas
