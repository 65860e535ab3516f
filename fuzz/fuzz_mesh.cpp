// Fuzz target: the mesh readers. Bytes that start like a GLB container go through
// read_glb_memory; anything else is read as a .gltf (JSON, buffers as data: URIs or files) and
// as an OBJ file. Whatever is accepted must be a mesh the renderers can use as is.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/error.h"
#include "formats/mesh_io.h"
#include "memfile.h"

namespace {

/// What read_mesh promises: triangles, indices in range, finite positions, unit normals.
void check(const matlas::TriangleMesh& m) {
  if (m.triangles.empty() || m.normals.size() != m.positions.size()) std::abort();
  for (const auto& t : m.triangles)
    for (std::uint32_t v : t)
      if (v >= m.positions.size()) std::abort();
  for (const auto& p : m.positions)
    if (!p.allFinite()) std::abort();
  for (const auto& n : m.normals)
    if (!(std::abs(n.norm() - 1.0f) < 1e-3f)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size >= 4 && std::memcmp(data, "glTF", 4) == 0) {
    try {
      check(matlas::read_glb_memory(data, size, "fuzz.glb"));
    } catch (const matlas::Error&) {
    }
    return 0;
  }
  const matlas::fuzz::MemFile file(data, size);
  try {
    check(matlas::read_gltf(file.path()));
  } catch (const matlas::Error&) {
  }
  try {
    check(matlas::read_obj(file.path()));
  } catch (const matlas::Error&) {
  }
  return 0;
}
