// Mesh files: the mesh type, OBJ by a small parser, and read_mesh (glTF: gltf_io.cpp).
#include "formats/mesh_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

#include <Eigen/Geometry>

#include "core/atomic_file.h"
#include "core/error.h"

namespace matlas {

// --- TriangleMesh ----------------------------------------------------------------------------

std::array<Eigen::Vector3f, 2> TriangleMesh::bounds() const {
  if (positions.empty()) throw Error("bounds of an empty mesh");
  Eigen::Vector3f lo = positions.front(), hi = positions.front();
  for (const auto& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

void TriangleMesh::compute_normals() {
  // In double precision: the face normal of a triangle with coordinates of 1e22 (finite floats)
  // overflows float (|n| ~ 1e44), and normalising infinity gave zero or NaN normals.
  std::vector<Eigen::Vector3d> sums(positions.size(), Eigen::Vector3d::Zero());
  for (const auto& t : triangles) {
    const Eigen::Vector3d p0 = positions[t[0]].cast<double>();
    const Eigen::Vector3d n = (positions[t[1]].cast<double>() - p0).cross(positions[t[2]].cast<double>() - p0);
    for (std::uint32_t v : t) sums[v] += n;  // |n| = twice the area: area weighting
  }
  normals.resize(positions.size());
  for (std::size_t i = 0; i < sums.size(); ++i) {
    const double len = sums[i].norm();
    normals[i] = len > 0 && std::isfinite(len) ? Eigen::Vector3f((sums[i] / len).cast<float>()) : Eigen::Vector3f(0, 0, 1);
  }
}

void TriangleMesh::append(const TriangleMesh& other) {
  const bool keep_normals = normals.size() == positions.size() &&
                            other.normals.size() == other.positions.size();
  const auto offset = static_cast<std::uint32_t>(positions.size());
  const bool was_empty = positions.empty();
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  if (keep_normals || (was_empty && other.normals.size() == other.positions.size()))
    normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  else
    normals.clear();
  for (auto t : other.triangles) triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

void check_mesh(TriangleMesh& mesh, const std::string& name) {
  if (mesh.triangles.empty()) throw file_error(name, "mesh has no triangles");
  check_mesh_size(mesh.positions.size(), mesh.triangles.size(), name);
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v >= mesh.positions.size())
        throw file_error(name, "triangle index " + std::to_string(v) + " out of range (" +
                                   std::to_string(mesh.positions.size()) + " vertices)");
  for (const auto& p : mesh.positions)
    if (!p.allFinite()) throw file_error(name, "mesh has NaN or infinite vertex positions");
  bool normals_ok = mesh.normals.size() == mesh.positions.size();
  if (normals_ok)
    for (auto& n : mesh.normals) {
      const float len = n.norm();
      if (!std::isfinite(len) || len < 1e-12f) {
        normals_ok = false;
        break;
      }
      n /= len;
    }
  if (!normals_ok) mesh.compute_normals();
}

void check_mesh_size(std::size_t vertices, std::size_t triangles, const std::string& name) {
  if (vertices > kMaxMeshVertices || triangles > kMaxMeshTriangles)
    throw file_error(name, "mesh too large: " + std::to_string(vertices) + " vertices and " + std::to_string(triangles) +
                               " triangles (at most " + std::to_string(kMaxMeshVertices) + " vertices and " +
                               std::to_string(kMaxMeshTriangles) + " triangles are read)");
}

namespace {

// --- OBJ ---------------------------------------------------------------------------------------

/// Parses "v", "v/t", "v//n", "v/t/n" into (v, n) 1-based indices (0 = absent; negative relative).
bool parse_face_vertex(std::string_view token, long& v, long& n) {
  v = n = 0;
  const std::size_t s1 = token.find('/');
  auto parse = [](std::string_view s, long& out) {
    if (s.empty()) return true;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size();
  };
  if (!parse(token.substr(0, s1), v) || v == 0) return false;
  if (s1 == std::string_view::npos) return true;
  const std::size_t s2 = token.find('/', s1 + 1);
  if (s2 == std::string_view::npos) return true;
  return parse(token.substr(s2 + 1), n);
}

}  // namespace

TriangleMesh read_obj(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  std::vector<Eigen::Vector3f> positions, normals;
  struct Corner {
    long v, n;
  };
  std::vector<std::array<Corner, 3>> faces;
  std::istringstream in(text);
  std::string line;
  std::size_t line_number = 0;
  auto fail = [&](const std::string& what) {
    return file_error(path, "line " + std::to_string(line_number) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    if (tag == "v" || tag == "vn") {
      Eigen::Vector3f p;
      if (!(ls >> p.x() >> p.y() >> p.z())) throw fail("expected three numbers after '" + tag + "'");
      (tag == "v" ? positions : normals).push_back(p);
    } else if (tag == "f") {
      std::vector<Corner> corners;
      std::string token;
      while (ls >> token) {
        Corner c{};
        if (!parse_face_vertex(token, c.v, c.n)) throw fail("bad face vertex '" + token + "'");
        // Negative indices count back from the current end.
        if (c.v < 0) c.v += static_cast<long>(positions.size()) + 1;
        if (c.n < 0) c.n += static_cast<long>(normals.size()) + 1;
        if (c.v <= 0 || c.v > static_cast<long>(positions.size()))
          throw fail("face refers to vertex " + token + " which is not defined");
        corners.push_back(c);
      }
      if (corners.size() < 3) throw fail("face with fewer than 3 vertices");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        faces.push_back({corners[0], corners[k], corners[k + 1]});
    }
  }
  // Flatten to one vertex per distinct (v, n) pair when normals are given per corner.
  TriangleMesh mesh;
  bool all_normals = !faces.empty() && !normals.empty();
  for (const auto& f : faces)
    for (const auto& c : f)
      if (c.n <= 0 || c.n > static_cast<long>(normals.size())) all_normals = false;
  if (!all_normals) {
    mesh.positions = std::move(positions);
    for (const auto& f : faces)
      mesh.triangles.push_back({static_cast<std::uint32_t>(f[0].v - 1),
                                static_cast<std::uint32_t>(f[1].v - 1),
                                static_cast<std::uint32_t>(f[2].v - 1)});
  } else {
    // A tree, not a sorted vector (inserting into the middle of a vector is quadratic in the
    // number of distinct pairs).
    std::map<std::pair<long, long>, std::uint32_t> ids;
    auto vertex_of = [&](const Corner& c) {
      const auto [it, added] = ids.try_emplace({c.v, c.n}, static_cast<std::uint32_t>(mesh.positions.size()));
      if (added) {
        mesh.positions.push_back(positions[static_cast<std::size_t>(c.v - 1)]);
        mesh.normals.push_back(normals[static_cast<std::size_t>(c.n - 1)]);
      }
      return it->second;
    };
    for (const auto& f : faces) mesh.triangles.push_back({vertex_of(f[0]), vertex_of(f[1]), vertex_of(f[2])});
  }
  check_mesh(mesh, path.string());
  return mesh;
}

void write_obj(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ostringstream out;
  out.precision(9);
  const bool normals = mesh.normals.size() == mesh.positions.size();
  for (const auto& p : mesh.positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  if (normals)
    for (const auto& n : mesh.normals) out << "vn " << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
  for (const auto& t : mesh.triangles) {
    out << 'f';
    for (std::uint32_t v : t) {
      out << ' ' << v + 1;
      if (normals) out << "//" << v + 1;
    }
    out << '\n';
  }
  write_file_atomic(path, out.str());
}

TriangleMesh read_mesh(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return read_obj(path);
  if (ext == ".glb" || ext == ".gltf") return read_gltf(path);
  throw file_error(path, "unknown mesh extension (expected .obj, .glb or .gltf)");
}

}  // namespace matlas
