// Mesh files: OBJ by a small parser, glTF through tinygltf (Debian's compiled libtinygltf) with
// KHR_draco_mesh_compression primitives decoded by Draco.
#include "formats/mesh_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

#include <Eigen/Geometry>
#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

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
  normals.assign(positions.size(), Eigen::Vector3f::Zero());
  for (const auto& t : triangles) {
    const Eigen::Vector3f n =
        (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    for (std::uint32_t v : t) normals[v] += n;  // |n| = twice the area: area weighting
  }
  for (auto& n : normals) {
    const float len = n.norm();
    n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(0, 0, 1);
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

namespace {

void validate(TriangleMesh& mesh, const std::string& name) {
  if (mesh.triangles.empty()) throw file_error(name, "mesh has no triangles");
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
    std::vector<std::pair<long, long>> keys;
    std::vector<std::uint32_t> ids;
    std::vector<std::pair<std::pair<long, long>, std::uint32_t>> map;
    auto vertex_of = [&](const Corner& c) {
      const std::pair<long, long> key{c.v, c.n};
      auto it = std::lower_bound(map.begin(), map.end(), key,
                                 [](const auto& e, const auto& k) { return e.first < k; });
      if (it != map.end() && it->first == key) return it->second;
      const auto id = static_cast<std::uint32_t>(mesh.positions.size());
      mesh.positions.push_back(positions[static_cast<std::size_t>(c.v - 1)]);
      mesh.normals.push_back(normals[static_cast<std::size_t>(c.n - 1)]);
      map.insert(it, {key, id});
      return id;
    };
    for (const auto& f : faces) mesh.triangles.push_back({vertex_of(f[0]), vertex_of(f[1]), vertex_of(f[2])});
  }
  validate(mesh, path.string());
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

// --- glTF --------------------------------------------------------------------------------------

namespace {

/// Reads accessor `index` as `components` floats per element (float, or normalised integers).
std::vector<float> read_float_accessor(const tinygltf::Model& model, int index, int components,
                                       const std::string& name) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size()))
    throw file_error(name, "accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
  if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)) != components)
    throw file_error(name, "accessor " + std::to_string(index) + " has the wrong element type");
  if (a.bufferView < 0 || a.sparse.isSparse)
    throw file_error(name, "accessor " + std::to_string(index) + " has no data (sparse or empty)");
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  const tinygltf::Buffer& buffer = model.buffers.at(static_cast<std::size_t>(view.buffer));
  const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (component_size <= 0) throw file_error(name, "accessor has an unknown component type");
  const std::size_t stride = a.ByteStride(view) > 0 ? static_cast<std::size_t>(a.ByteStride(view))
                                                    : static_cast<std::size_t>(component_size * components);
  const std::size_t start = view.byteOffset + a.byteOffset;
  const std::size_t element = static_cast<std::size_t>(component_size * components);
  if (a.count > 0 && start + (a.count - 1) * stride + element > buffer.data.size())
    throw file_error(name, "accessor " + std::to_string(index) + " runs past its buffer");
  std::vector<float> out(a.count * static_cast<std::size_t>(components));
  for (std::size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = buffer.data.data() + start + i * stride;
    for (int c = 0; c < components; ++c) {
      float v = 0;
      const unsigned char* q = p + c * component_size;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, q, 4); break;
        case TINYGLTF_COMPONENT_TYPE_BYTE: v = std::max(static_cast<float>(static_cast<signed char>(*q)) / 127.0f, -1.0f); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = static_cast<float>(*q) / 255.0f; break;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
          std::int16_t s;
          std::memcpy(&s, q, 2);
          v = std::max(static_cast<float>(s) / 32767.0f, -1.0f);
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, q, 2);
          v = static_cast<float>(s) / 65535.0f;
          break;
        }
        default: throw file_error(name, "unsupported vertex component type");
      }
      out[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)] = v;
    }
  }
  return out;
}

std::vector<std::uint32_t> read_index_accessor(const tinygltf::Model& model, int index,
                                               const std::string& name) {
  const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(index));
  if (a.bufferView < 0) throw file_error(name, "index accessor has no data");
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  const tinygltf::Buffer& buffer = model.buffers.at(static_cast<std::size_t>(view.buffer));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (size != 1 && size != 2 && size != 4) throw file_error(name, "bad index component type");
  const std::size_t stride = a.ByteStride(view) > 0 ? static_cast<std::size_t>(a.ByteStride(view))
                                                    : static_cast<std::size_t>(size);
  const std::size_t start = view.byteOffset + a.byteOffset;
  if (a.count > 0 && start + (a.count - 1) * stride + static_cast<std::size_t>(size) > buffer.data.size())
    throw file_error(name, "index accessor runs past its buffer");
  std::vector<std::uint32_t> out(a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = buffer.data.data() + start + i * stride;
    if (size == 1) out[i] = *p;
    if (size == 2) {
      std::uint16_t s;
      std::memcpy(&s, p, 2);
      out[i] = s;
    }
    if (size == 4) std::memcpy(&out[i], p, 4);
  }
  return out;
}

/// Decodes a KHR_draco_mesh_compression primitive into positions, normals and triangles.
TriangleMesh decode_draco(const tinygltf::Model& model, const tinygltf::Value& ext,
                          const std::string& name) {
  const int view_index = ext.Get("bufferView").GetNumberAsInt();
  if (view_index < 0 || view_index >= static_cast<int>(model.bufferViews.size()))
    throw file_error(name, "Draco extension refers to a missing buffer view");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  const tinygltf::Buffer& buffer = model.buffers.at(static_cast<std::size_t>(view.buffer));
  if (view.byteOffset + view.byteLength > buffer.data.size())
    throw file_error(name, "Draco buffer view runs past its buffer");
  draco::DecoderBuffer input;
  input.Init(reinterpret_cast<const char*>(buffer.data.data() + view.byteOffset), view.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&input);
  if (!decoded.ok())
    throw file_error(name, std::string("cannot decode Draco mesh: ") + decoded.status().error_msg());
  const std::unique_ptr<draco::Mesh> dm = std::move(decoded).value();
  const tinygltf::Value& attributes = ext.Get("attributes");
  auto attribute = [&](const char* key) -> const draco::PointAttribute* {
    if (!attributes.Has(key)) return nullptr;
    return dm->GetAttributeByUniqueId(static_cast<std::uint32_t>(attributes.Get(key).GetNumberAsInt()));
  };
  const draco::PointAttribute* pos = attribute("POSITION");
  const draco::PointAttribute* nor = attribute("NORMAL");
  if (pos == nullptr) throw file_error(name, "Draco mesh has no POSITION attribute");
  TriangleMesh mesh;
  const std::uint32_t points = dm->num_points();
  mesh.positions.resize(points);
  if (nor) mesh.normals.resize(points);
  for (std::uint32_t p = 0; p < points; ++p) {
    float v[3] = {0, 0, 0};
    pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, v);
    mesh.positions[p] = {v[0], v[1], v[2]};
    if (nor) {
      nor->ConvertValue<float>(nor->mapped_index(draco::PointIndex(p)), 3, v);
      mesh.normals[p] = {v[0], v[1], v[2]};
    }
  }
  for (std::uint32_t f = 0; f < dm->num_faces(); ++f) {
    const auto& face = dm->face(draco::FaceIndex(f));
    mesh.triangles.push_back({face[0].value(), face[1].value(), face[2].value()});
  }
  return mesh;
}

TriangleMesh read_primitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                            const std::string& name) {
  auto draco_ext = prim.extensions.find("KHR_draco_mesh_compression");
  if (draco_ext != prim.extensions.end()) return decode_draco(model, draco_ext->second, name);
  auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) throw file_error(name, "primitive without POSITION");
  TriangleMesh mesh;
  const std::vector<float> pos = read_float_accessor(model, pos_it->second, 3, name);
  for (std::size_t i = 0; i + 2 < pos.size(); i += 3) mesh.positions.emplace_back(pos[i], pos[i + 1], pos[i + 2]);
  if (auto n_it = prim.attributes.find("NORMAL"); n_it != prim.attributes.end()) {
    const std::vector<float> nor = read_float_accessor(model, n_it->second, 3, name);
    for (std::size_t i = 0; i + 2 < nor.size(); i += 3) mesh.normals.emplace_back(nor[i], nor[i + 1], nor[i + 2]);
  }
  std::vector<std::uint32_t> idx;
  if (prim.indices >= 0) {
    idx = read_index_accessor(model, prim.indices, name);
  } else {
    idx.resize(mesh.positions.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t i = 0; i + 2 < idx.size(); i += 3) mesh.triangles.push_back({idx[i], idx[i + 1], idx[i + 2]});
  return mesh;
}

Eigen::Matrix4d node_matrix(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m(r, c) = node.matrix[static_cast<std::size_t>(4 * c + r)];
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    t.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]).normalized());
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

void collect(const tinygltf::Model& model, int node_index, const Eigen::Matrix4d& parent,
             TriangleMesh& out, const std::string& name, int depth) {
  if (node_index < 0 || node_index >= static_cast<int>(model.nodes.size()) || depth > 64)
    throw file_error(name, "bad node hierarchy");
  const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(node_index)];
  const Eigen::Matrix4d m = parent * node_matrix(node);
  if (node.mesh >= 0) {
    const Eigen::Matrix3d normal_matrix = m.topLeftCorner<3, 3>().inverse().transpose();
    for (const auto& prim : model.meshes.at(static_cast<std::size_t>(node.mesh)).primitives) {
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
      TriangleMesh part = read_primitive(model, prim, name);
      for (auto& p : part.positions)
        p = (m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0)).head<3>().cast<float>();
      for (auto& n : part.normals) n = (normal_matrix * n.cast<double>()).normalized().cast<float>();
      if (m.topLeftCorner<3, 3>().determinant() < 0)
        for (auto& t : part.triangles) std::swap(t[1], t[2]);
      for (const auto& t : part.triangles)
        for (std::uint32_t v : t)
          if (v >= part.positions.size()) throw file_error(name, "triangle index out of range");
      out.append(part);
    }
  }
  for (int child : node.children) collect(model, child, m, out, name, depth + 1);
}

TriangleMesh flatten(const tinygltf::Model& model, const std::string& name) {
  TriangleMesh mesh;
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    for (int node : model.scenes.at(static_cast<std::size_t>(scene)).nodes)
      collect(model, node, Eigen::Matrix4d::Identity(), mesh, name, 0);
  } else {
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      collect(model, static_cast<int>(i), Eigen::Matrix4d::Identity(), mesh, name, 0);
  }
  validate(mesh, name);
  return mesh;
}

/// tinygltf 2.7 insists that index accessors have a buffer view, which Draco-compressed
/// primitives do not: drop "indices" from those primitives (Draco supplies the triangles).
bool patch_draco_primitives(nlohmann::json& gltf) {
  bool changed = false;
  if (!gltf.contains("meshes") || !gltf["meshes"].is_array()) return false;
  for (auto& mesh : gltf["meshes"]) {
    if (!mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (auto& prim : mesh["primitives"])
      if (prim.contains("extensions") && prim["extensions"].contains("KHR_draco_mesh_compression") &&
          prim.contains("indices")) {
        prim.erase("indices");
        changed = true;
      }
  }
  return changed;
}

std::uint32_t read_u32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

/// The GLB container with its JSON chunk patched (see patch_draco_primitives), or the input.
std::string patch_glb(const unsigned char* data, std::size_t bytes) {
  std::string out(reinterpret_cast<const char*>(data), bytes);
  if (bytes < 20 || std::memcmp(data, "glTF", 4) != 0) return out;
  const std::uint32_t json_length = read_u32(data + 12);
  if (std::memcmp(data + 16, "JSON", 4) != 0 || 20 + static_cast<std::size_t>(json_length) > bytes) return out;
  nlohmann::json gltf = nlohmann::json::parse(data + 20, data + 20 + json_length, nullptr, false);
  if (gltf.is_discarded() || !patch_draco_primitives(gltf)) return out;
  std::string json = gltf.dump();
  while (json.size() % 4) json.push_back(' ');
  const std::string rest(reinterpret_cast<const char*>(data) + 20 + json_length, bytes - 20 - json_length);
  auto u32 = [](std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  out.assign(reinterpret_cast<const char*>(data), 8);
  u32(out, static_cast<std::uint32_t>(20 + json.size() + rest.size()));
  u32(out, static_cast<std::uint32_t>(json.size()));
  out += "JSON";
  out += json;
  out += rest;
  return out;
}

bool no_images(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;  // textures are not used: skip decoding them
}

}  // namespace

TriangleMesh read_glb_memory(const void* data, std::size_t bytes, const std::string& name) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(no_images, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  if (bytes > 0xffffffffu) throw file_error(name, "glTF file too large");
  const std::string glb = patch_glb(static_cast<const unsigned char*>(data), bytes);
  if (!loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                   static_cast<unsigned int>(glb.size()), ""))
    throw file_error(name, "cannot read glTF binary: " + (err.empty() ? warn : err));
  return flatten(model, name);
}

TriangleMesh read_gltf(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".glb") {
    const std::string bytes = read_file(path);
    return read_glb_memory(bytes.data(), bytes.size(), path.string());
  }
  if (!std::filesystem::is_regular_file(path)) throw file_error(path, "no such file");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(no_images, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  nlohmann::json gltf = nlohmann::json::parse(read_file(path), nullptr, false);
  if (gltf.is_discarded()) throw file_error(path, "cannot read glTF: malformed JSON");
  patch_draco_primitives(gltf);
  const std::string text = gltf.dump();
  if (!loader.LoadASCIIFromString(&model, &err, &warn, text.c_str(), static_cast<unsigned int>(text.size()),
                                  path.parent_path().string()))
    throw file_error(path, "cannot read glTF: " + (err.empty() ? warn : err));
  return flatten(model, path.string());
}

TriangleMesh read_mesh(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return read_obj(path);
  if (ext == ".glb" || ext == ".gltf") return read_gltf(path);
  throw file_error(path, "unknown mesh extension (expected .obj, .glb or .gltf)");
}

}  // namespace matlas
