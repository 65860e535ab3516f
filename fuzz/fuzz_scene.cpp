// Fuzz target: JSON scene files (pathtrace/scene_spec.h) through load_scene, then, for what is
// accepted, the scene itself: meshes read, Embree's build, camera rays and their first hits.
// Input: the scene's JSON, optionally followed by a NUL byte and the bytes of a mesh file (GLB,
// glTF JSON or OBJ by its first byte) that every mesh object of the scene then uses. Environment
// maps are dropped (loading installed maps would only measure the disk).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>
#include <sys/mman.h>
#include <unistd.h>

#include "core/error.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/world.h"

namespace {

/// A memfd reached through a symbolic link of a chosen name (the readers go by extension).
class NamedMemFile {
public:
  NamedMemFile(const std::filesystem::path& dir, const std::string& name) : link_(dir / name) {
    fd_ = ::memfd_create("matlas-fuzz", MFD_CLOEXEC);
    std::filesystem::remove(link_);
    std::filesystem::create_symlink("/proc/self/fd/" + std::to_string(fd_), link_);
  }
  void assign(std::string_view bytes) const {
    if (::ftruncate(fd_, 0) != 0) std::abort();
    for (std::size_t done = 0; done < bytes.size();) {
      const ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(done));
      if (n <= 0) std::abort();
      done += static_cast<std::size_t>(n);
    }
  }
  const std::filesystem::path& path() const { return link_; }

private:
  int fd_ = -1;
  std::filesystem::path link_;
};

struct Files {
  std::filesystem::path dir;
  NamedMemFile *scene, *glb, *gltf, *obj;
};

std::filesystem::path* scratch = nullptr;  // removed at exit

const Files& files() {
  static const Files f = [] {
    Files out;
    out.dir = std::filesystem::temp_directory_path() / ("matlas-fuzz-scene-" + std::to_string(::getpid()));
    std::filesystem::create_directories(out.dir);
    scratch = new std::filesystem::path(out.dir);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(*scratch, ec);
    });
    out.scene = new NamedMemFile(out.dir, "scene.json");
    out.glb = new NamedMemFile(out.dir, "mesh.glb");
    out.gltf = new NamedMemFile(out.dir, "mesh.gltf");
    out.obj = new NamedMemFile(out.dir, "mesh.obj");
    return out;
  }();
  return f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = bytes.find('\0');
  const Files& f = files();
  f.scene->assign(bytes.substr(0, nul));
  const NamedMemFile* mesh = nullptr;
  if (nul != std::string_view::npos) {
    const std::string_view m = bytes.substr(nul + 1);
    mesh = m.substr(0, 4) == "glTF" ? f.glb : m.substr(0, 1) == "{" ? f.gltf : f.obj;
    mesh->assign(m);
  }
  try {
    matlas::pathtrace::SceneSpec spec = matlas::pathtrace::load_scene(f.scene->path().string());
    // What parse_scene accepts, scene_to_json writes and parse_scene reads back the same.
    if (matlas::pathtrace::scene_to_json(matlas::pathtrace::parse_scene(matlas::pathtrace::scene_to_json(spec), "again")) !=
        matlas::pathtrace::scene_to_json(spec))
      std::abort();
    spec.environment.map.clear();
    for (auto& o : spec.objects) {
      if (o.shape != "mesh") continue;
      if (!mesh) return 0;  // installed meshes only measure the disk
      o.mesh = mesh->path().string();
    }
    const matlas::pathtrace::World world(spec);
    for (int k = 0; k < 9; ++k) {
      matlas::Vec3 origin, dir;
      world.camera_ray(4 * (k % 3) + 1.5, 4 * (k / 3) + 1.5, 12, 12, &origin, &dir);
      if (!origin.allFinite() || !dir.allFinite()) std::abort();
      (void)world.intersect(origin, dir);
    }
  } catch (const matlas::Error&) {
  }
  return 0;
}
