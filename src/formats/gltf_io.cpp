// glTF meshes through tinygltf (Debian's compiled libtinygltf), KHR_draco_mesh_compression
// primitives decoded by Draco. Everything the JSON says (indices of accessors, views, buffers,
// nodes, meshes; offsets, counts and strides) is checked before use: tinygltf checks little.
#include <algorithm>
#include <cstring>
#include <limits>
#include <string_view>

#include <Eigen/Geometry>
#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <sys/stat.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/mesh_io.h"

namespace matlas {

namespace {

/// The element `index` of a list of the model, or a matlas::Error naming what refers to it.
template <class T>
const T& element(const std::vector<T>& list, long long index, const char* kind, const std::string& name) {
  if (index < 0 || static_cast<unsigned long long>(index) >= list.size())
    throw file_error(name, std::string("refers to ") + kind + " " + std::to_string(index) + ", which does not exist (" +
                               std::to_string(list.size()) + " defined)");
  return list[static_cast<std::size_t>(index)];
}

/// The bytes of buffer view `index`, checked to lie inside its buffer.
std::span<const unsigned char> view_bytes(const tinygltf::Model& model, long long index, const std::string& name) {
  const tinygltf::BufferView& view = element(model.bufferViews, index, "buffer view", name);
  const tinygltf::Buffer& buffer = element(model.buffers, view.buffer, "buffer", name);
  const std::size_t size = buffer.data.size();
  if (view.byteOffset > size || view.byteLength > size - view.byteOffset)
    throw file_error(name, "buffer view " + std::to_string(index) + " (" + std::to_string(view.byteLength) +
                               " bytes at offset " + std::to_string(view.byteOffset) + ") runs past its buffer (" +
                               std::to_string(size) + " bytes)");
  return {buffer.data.data() + view.byteOffset, view.byteLength};
}

/// Where the elements of an accessor lie: count elements of `element_size` bytes, `stride` apart.
struct AccessorBytes {
  const unsigned char* data = nullptr;
  std::size_t count = 0, stride = 0;
};

/// Accessor `a`'s elements, checked to lie inside its buffer view without overflow: a count near
/// 2^64 / 3 must not wrap (count - 1) * stride around to a small number.
AccessorBytes accessor_bytes(const tinygltf::Model& model, const tinygltf::Accessor& a, std::size_t element_size,
                             const std::string& what, const std::string& name) {
  if (a.bufferView < 0 || a.sparse.isSparse) throw file_error(name, what + " has no data (sparse or empty)");
  const std::span<const unsigned char> view = view_bytes(model, a.bufferView, name);
  const int declared = a.ByteStride(model.bufferViews[static_cast<std::size_t>(a.bufferView)]);
  if (declared <= 0) throw file_error(name, what + " has an invalid byte stride");
  const auto stride = static_cast<std::size_t>(declared);
  AccessorBytes out{nullptr, a.count, stride};
  if (a.count == 0) return out;
  if (a.byteOffset > view.size() || element_size > view.size() - a.byteOffset ||
      a.count - 1 > (view.size() - a.byteOffset - element_size) / stride)
    throw file_error(name, what + " (" + std::to_string(a.count) + " elements of " + std::to_string(element_size) +
                               " bytes, " + std::to_string(stride) + " apart, at offset " + std::to_string(a.byteOffset) +
                               ") runs past its buffer view (" + std::to_string(view.size()) + " bytes)");
  out.data = view.data() + a.byteOffset;
  return out;
}

/// Reads accessor `index` as `components` floats per element (float, or normalised integers).
std::vector<float> read_float_accessor(const tinygltf::Model& model, int index, int components,
                                       const std::string& name) {
  const std::string what = "accessor " + std::to_string(index);
  const tinygltf::Accessor& a = element(model.accessors, index, "accessor", name);
  if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)) != components)
    throw file_error(name, what + " has the wrong element type");
  const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (component_size <= 0) throw file_error(name, what + " has an unknown component type");
  const auto ncomp = static_cast<std::size_t>(components);
  const AccessorBytes bytes =
      accessor_bytes(model, a, static_cast<std::size_t>(component_size) * ncomp, what, name);
  check_mesh_size(bytes.count, 0, name);  // bounded by the buffer already; this bounds count * components
  std::vector<float> out(bytes.count * ncomp);
  for (std::size_t i = 0; i < bytes.count; ++i) {
    const unsigned char* p = bytes.data + i * bytes.stride;
    for (std::size_t c = 0; c < ncomp; ++c) {
      float v = 0;
      const unsigned char* q = p + c * static_cast<std::size_t>(component_size);
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
      out[i * ncomp + c] = v;
    }
  }
  return out;
}

std::vector<std::uint32_t> read_index_accessor(const tinygltf::Model& model, int index, const std::string& name) {
  const std::string what = "index accessor " + std::to_string(index);
  const tinygltf::Accessor& a = element(model.accessors, index, "accessor", name);
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (size != 1 && size != 2 && size != 4) throw file_error(name, what + " has a bad component type");
  const AccessorBytes bytes = accessor_bytes(model, a, static_cast<std::size_t>(size), what, name);
  check_mesh_size(0, bytes.count / 3, name);
  std::vector<std::uint32_t> out(bytes.count);
  for (std::size_t i = 0; i < bytes.count; ++i) {
    const unsigned char* p = bytes.data + i * bytes.stride;
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
  const tinygltf::Value& view_index = ext.Get("bufferView");
  if (!view_index.IsNumber()) throw file_error(name, "Draco extension without a buffer view");
  const std::span<const unsigned char> view = view_bytes(model, view_index.GetNumberAsInt(), name);
  draco::DecoderBuffer input;
  input.Init(reinterpret_cast<const char*>(view.data()), view.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&input);
  if (!decoded.ok())
    throw file_error(name, std::string("cannot decode Draco mesh: ") + decoded.status().error_msg());
  const std::unique_ptr<draco::Mesh> dm = std::move(decoded).value();
  check_mesh_size(dm->num_points(), dm->num_faces(), name);
  const tinygltf::Value& attributes = ext.Get("attributes");
  auto attribute = [&](const char* key) -> const draco::PointAttribute* {
    if (!attributes.Has(key) || !attributes.Get(key).IsNumber()) return nullptr;
    const int id = attributes.Get(key).GetNumberAsInt();
    return id < 0 ? nullptr : dm->GetAttributeByUniqueId(static_cast<std::uint32_t>(id));
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

/// The triangles of a node graph in world space. Every node visit and primitive instance counts
/// against kMaxGltfInstances, and a node met again on its own path (a cycle) is refused.
struct Flattening {
  const tinygltf::Model& model;
  const std::string& name;
  TriangleMesh mesh;
  std::size_t instances = 0;
  std::vector<bool> on_path = std::vector<bool>(model.nodes.size(), false);
  static constexpr int kMaxDepth = 64;

  void count_instance() {
    if (++instances > kMaxGltfInstances)
      throw file_error(name, "the node graph instances more than " + std::to_string(kMaxGltfInstances) +
                                 " nodes and primitives (nodes shared by several parents multiply)");
  }

  void collect(int node_index, const Eigen::Matrix4d& parent, int depth = 0) {
    const tinygltf::Node& node = element(model.nodes, node_index, "node", name);
    const auto index = static_cast<std::size_t>(node_index);
    if (on_path[index]) throw file_error(name, "node " + std::to_string(node_index) + " is its own ancestor (a cycle)");
    if (depth > kMaxDepth) throw file_error(name, "the node graph is deeper than " + std::to_string(kMaxDepth) + " levels");
    count_instance();
    const Eigen::Matrix4d m = parent * node_matrix(node);
    if (node.mesh >= 0) {
      const Eigen::Matrix3d normal_matrix = m.topLeftCorner<3, 3>().inverse().transpose();
      for (const auto& prim : element(model.meshes, node.mesh, "mesh", name).primitives) {
        count_instance();
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
        TriangleMesh part = read_primitive(model, prim, name);
        check_mesh_size(mesh.positions.size() + part.positions.size(), mesh.triangles.size() + part.triangles.size(),
                        name);
        for (auto& p : part.positions) p = (m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0)).head<3>().cast<float>();
        for (auto& n : part.normals) n = (normal_matrix * n.cast<double>()).normalized().cast<float>();
        if (m.topLeftCorner<3, 3>().determinant() < 0)
          for (auto& t : part.triangles) std::swap(t[1], t[2]);
        for (const auto& t : part.triangles)
          for (std::uint32_t v : t)
            if (v >= part.positions.size()) throw file_error(name, "triangle index out of range");
        mesh.append(part);
      }
    }
    on_path[index] = true;
    for (int child : node.children) collect(child, m, depth + 1);
    on_path[index] = false;
  }
};

TriangleMesh flatten(const tinygltf::Model& model, const std::string& name) {
  Flattening f{model, name, {}};
  if (!model.scenes.empty()) {
    const tinygltf::Scene& scene = element(model.scenes, std::max(model.defaultScene, 0), "scene", name);
    for (int node : scene.nodes) f.collect(node, Eigen::Matrix4d::Identity());
  } else {
    for (std::size_t i = 0; i < model.nodes.size(); ++i) f.collect(static_cast<int>(i), Eigen::Matrix4d::Identity());
  }
  check_mesh(f.mesh, name);
  return std::move(f.mesh);
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

/// tinygltf converts "extras" and "extensions" to its own values recursively, a stack frame per
/// level: JSON nested deeper than kMaxJsonDepth (glTF's own structure is under 10 levels) is
/// refused before it gets there (a 256 KiB file can nest 128 Ki levels).
constexpr int kMaxJsonDepth = 256;

void check_json_depth(std::string_view json, const std::string& name) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : json) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw file_error(name, "glTF JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

bool no_images(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;  // textures are not used: skip decoding them
}

/// External buffers (and images, skipped) are found and read as every input is: tinygltf's own
/// callbacks fopen a file to see whether it exists (blocking on a FIFO) and read it whole with
/// std::ifstream; here a stat answers, open_regular_file refuses FIFOs and devices, and a buffer
/// over kMaxGltfBufferBytes is refused before it is read.
bool file_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  try {
    const int fd = open_regular_file(path, "a glTF buffer");
    struct stat st {};
    const bool ok = ::fstat(fd, &st) == 0 && static_cast<std::uint64_t>(st.st_size) <= kMaxGltfBufferBytes;
    if (ok) {
      out->resize(static_cast<std::size_t>(st.st_size));
      try {
        read_exact_at(fd, path, out->data(), out->size(), 0);
      } catch (...) {
        ::close(fd);
        throw;
      }
    }
    ::close(fd);
    if (!ok) throw file_error(path, "larger than " + std::to_string(kMaxGltfBufferBytes) + " bytes, or unreadable");
    return true;
  } catch (const Error& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

tinygltf::TinyGLTF make_loader() {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(no_images, nullptr);
  loader.SetFsCallbacks({&file_exists, &tinygltf::ExpandFilePath, &read_whole_file, nullptr, nullptr});
  return loader;
}

}  // namespace

TriangleMesh read_glb_memory(const void* data, std::size_t bytes, const std::string& name) {
  tinygltf::TinyGLTF loader = make_loader();
  tinygltf::Model model;
  std::string err, warn;
  if (bytes > 0xffffffffu) throw file_error(name, "glTF file too large");
  if (bytes >= 20 && std::memcmp(data, "glTF", 4) == 0) {  // the JSON chunk, as much of it as there is
    const auto* p = static_cast<const char*>(data);
    check_json_depth(std::string_view(p + 20, std::min<std::size_t>(read_u32(reinterpret_cast<const unsigned char*>(p) + 12),
                                                                      bytes - 20)),
                     name);
  }
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
  tinygltf::TinyGLTF loader = make_loader();
  tinygltf::Model model;
  std::string err, warn;
  const std::string text_in = read_file(path);
  check_json_depth(text_in, path.string());
  nlohmann::json gltf = nlohmann::json::parse(text_in, nullptr, false);
  if (gltf.is_discarded()) throw file_error(path, "cannot read glTF: malformed JSON");
  patch_draco_primitives(gltf);
  const std::string text = gltf.dump();
  if (!loader.LoadASCIIFromString(&model, &err, &warn, text.c_str(), static_cast<unsigned int>(text.size()),
                                  path.parent_path().string()))
    throw file_error(path, "cannot read glTF: " + (err.empty() ? warn : err));
  return flatten(model, path.string());
}

}  // namespace matlas
