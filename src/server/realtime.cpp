#include "server/realtime.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdint>

#include "atlas/zonal_cache.h"
#include "core/combination.h"
#include "formats/half_float.h"
#include "formats/mesh_io.h"
#include "manifold/model.h"
#include "render/assets.h"
#include "render/render.h"
#include "render/scene.h"
#include "server/http_error.h"
#include "zonal/coefficients.h"
#include "zonal/shade.h"
#include "zonal/shader_layout.h"

namespace matlas::server {

namespace {

std::string float_bytes(const std::vector<float>& v) {
  std::string out(v.size() * sizeof(float), '\0');
  std::memcpy(out.data(), v.data(), out.size());  // little-endian hosts (x86-64, the only target)
  return out;
}

render::Environment load_environment(const std::string& name, double rotation) {
  if (name == "constant") return render::Environment::constant(Rgb::Constant(1.0));
  return render::Environment::load(resolve_environment(name), rotation);
}

zonal::PrefilterSettings prefilter_settings() {
  zonal::PrefilterSettings s;
  s.bands = kRealtimeBands;
  s.lobes = zonal::kDefaultLobes;
  return s;
}

}  // namespace

Realtime::Realtime(const Model& model, std::vector<std::string> environments, std::vector<std::string> objects)
    : model_(model), envs_(std::move(environments)), objects_(std::move(objects)) {}

const zonal::CoefficientSet& Realtime::set() {
  std::lock_guard lock(coefficients_mutex_);
  if (!set_) {
    const zonal::ProjectionSettings settings{kRealtimeBands, kRealtimeThetaO, 128, 256, zonal::kDefaultLobes,
                                             kRealtimeRingFloor};
    atlas::CachedCoefficients c =
        atlas::cached_model_coefficients(model_, settings, atlas::zonal_cache_path(model_.path(), kRealtimeBands));
    auto set = std::make_unique<zonal::CoefficientSet>(std::move(c.set));
    packed_ = float_bytes(zonal::pack_coefficients(*set));
    seconds_ = c.seconds;
    cache_ = c.loaded ? "loaded" : "computed";
    cache_note_ = c.note;
    set_ = std::move(set);
  }
  return *set_;
}

nlohmann::json Realtime::info() {
  const zonal::CoefficientSet& s = set();
  const zonal::ZonalBasis basis(s.settings.bands);
  nlohmann::json alpha = nlohmann::json::array(), band = nlohmann::json::array(), theta = nlohmann::json::array();
  for (std::size_t j = 0; j < basis.size(); ++j) {
    alpha.push_back(basis.alpha(j));
    band.push_back(basis.band(j));
  }
  for (int t = 0; t < s.settings.theta_o_count; ++t)
    theta.push_back(zonal::ZonalCoefficients::theta_o(t, s.settings.theta_o_count));
  const render::Camera camera;
  const MerlDims lights = zonal::LightTable::reduced_dims(model_.dims());
  return {{"bands", s.settings.bands},
          {"theta_o_count", s.settings.theta_o_count},
          {"coefficients", basis.size() + s.settings.lobes.size()},
          {"materials", s.materials.size()},
          {"alpha", alpha},
          {"band", band},
          {"theta_o", theta},
          {"layout", "float32 [materials + 1][theta_o_count][coefficients][3], the mean first; per theta_o the "
                     "(bands + 1)(bands + 2)/2 rotated-ZH terms, then one weight per lobe"},
          {"seconds", seconds_},
          {"cache", cache_},
          {"cache_note", cache_note_},
          {"light_table",
           {{"theta_h", lights.theta_h},
            {"theta_d", lights.theta_d},
            {"phi_d", lights.phi_d},
            {"layout", "float16 [theta_h][theta_d][phi_d][3] (POST /api/realtime/lights)"}}},
          {"environments", envs_},
          {"objects", objects_},
          {"camera",
           {{"position", {camera.position.x(), camera.position.y(), camera.position.z()}},
            {"target", {camera.target.x(), camera.target.y(), camera.target.z()}},
            {"fov_degrees", camera.fov_degrees}}}};
}

const std::string& Realtime::coefficients() {
  set();
  return packed_;
}

const Realtime::Prefiltered& Realtime::prefiltered(const std::string& name) {
  if (std::find(envs_.begin(), envs_.end(), name) == envs_.end())
    throw HttpError(404, "no environment " + quoted_excerpt(name) + " (the installed ones are listed by /api/realtime)");
  std::lock_guard lock(env_mutex_);
  auto it = envs_cache_.find(name);
  if (it == envs_cache_.end()) {
    Prefiltered p;
    const auto start = std::chrono::steady_clock::now();
    const render::Environment raw = load_environment(name, 0.0);
    zonal::LightSplit split = zonal::split_lights(raw, kRealtimeLights);
    p.maps = std::make_shared<const zonal::PrefilteredEnvironment>(split.residual, prefilter_settings());
    const zonal::EnvironmentAtlas atlas = zonal::pack_environment(*p.maps);
    const zonal::EnvironmentAtlas detail = zonal::pack_detail(*p.maps, raw, zonal::kDetailSide);
    std::vector<float> lights;
    for (const zonal::LightPoint& l : split.points)
      for (double v : {l.direction.x(), l.direction.y(), l.direction.z(), l.power[0], l.power[1], l.power[2]})
        lights.push_back(static_cast<float>(v));
    p.lights = std::move(split.points);
    p.atlas = std::make_shared<const std::string>(float_bytes(atlas.values) + float_bytes(detail.values) +
                                                  float_bytes(lights));
    p.shape = {{"name", name},
               {"bands", atlas.bands},
               {"width", atlas.width},
               {"height", atlas.height},
               {"detail",
                {{"offset", atlas.values.size()},
                 {"lobes", p.maps->lobes()},
                 {"layers", detail.bands + 1},
                 {"width", detail.width},
                 {"height", detail.height}}},
               {"lights",
                {{"offset", atlas.values.size() + detail.values.size()},
                 {"count", p.lights.size()},
                 {"texels", split.texels},
                 {"fraction", split.light_fraction}}},
               {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
    it = envs_cache_.emplace(name, std::move(p)).first;
  }
  return it->second;
}

std::pair<nlohmann::json, std::shared_ptr<const std::string>> Realtime::environment(const std::string& name) {
  const Prefiltered& p = prefiltered(name);
  return {p.shape, p.atlas};
}

std::string Realtime::mesh(const std::string& name) const {
  if (name == "sphere" || std::find(objects_.begin(), objects_.end(), name) == objects_.end())
    throw HttpError(404, "no mesh " + quoted_excerpt(name) + " (the sphere is built by the page)");
  const TriangleMesh mesh = *render::place_object(read_mesh(resolve_mesh(name))).mesh;
  const auto v = static_cast<std::uint32_t>(mesh.vertex_count()), t = static_cast<std::uint32_t>(mesh.triangle_count());
  std::string out(8 + (std::size_t{v} * 6 + std::size_t{t} * 3) * 4, '\0');
  char* p = out.data();
  auto put = [&p](const void* data, std::size_t bytes) {
    std::memcpy(p, data, bytes);
    p += bytes;
  };
  put(&v, 4);
  put(&t, 4);
  for (const auto& x : mesh.positions) put(x.data(), 12);
  for (const auto& n : mesh.normals) put(n.data(), 12);
  for (const auto& tri : mesh.triangles) put(tri.data(), 12);
  return out;
}

const atlas::ModelLightTables& Realtime::light_tables() {
  std::lock_guard lock(lights_mutex_);
  if (!light_tables_) light_tables_ = std::make_unique<atlas::ModelLightTables>(model_);
  return *light_tables_;
}

std::string Realtime::light_table(const Eigen::VectorXd& w) {
  const zonal::LightTable t = light_tables().at(w);
  std::string out(t.values().size() * 2, '\0');
  auto* p = reinterpret_cast<unsigned char*>(out.data());
  for (float v : t.values()) {
    const std::uint16_t h = float_to_half(v);
    *p++ = static_cast<unsigned char>(h & 0xff);
    *p++ = static_cast<unsigned char>(h >> 8);
  }
  return out;
}

Realtime::Reference Realtime::reference(const Eigen::VectorXd& w, const std::string& env, double rotation, int size) {
  const zonal::CoefficientSet& s = set();
  // m(w) = c_0 mean + sum w_i z_i (core/combination.h), and the coefficients are linear in the table.
  std::vector<const zonal::ZonalCoefficients*> parts{&*s.mean};
  for (const auto& material : s.materials) parts.push_back(&material);
  const Eigen::VectorXd a = Combination(w).coefficients();
  const std::vector<double> weights(a.data(), a.data() + a.size());
  const zonal::ZonalCoefficients c = zonal::combine(parts, weights);
  // The prefiltered maps of the unrotated environment, as the page has them; a rotation is
  // prefiltered anew (the page rotates its lookups instead, which is the same integral).
  const Prefiltered& unrotated = prefiltered(env);
  std::shared_ptr<const zonal::PrefilteredEnvironment> maps = unrotated.maps;
  std::vector<zonal::LightPoint> lights = unrotated.lights;
  if (rotation != 0.0) {
    zonal::LightSplit split = zonal::split_lights(load_environment(env, rotation), kRealtimeLights);
    maps = std::make_shared<const zonal::PrefilteredEnvironment>(split.residual, prefilter_settings());
    lights = std::move(split.points);
  }
  const zonal::LightTable table = light_tables().at(w);
  const zonal::LightTableMaterial material(table);
  const zonal::DirectLights direct{&lights, &material};
  render::SceneDescription description;
  description.environment = "constant";
  description.show_environment = false;
  const render::Scene scene(description);
  const zonal::ZonalBasis basis(s.settings.bands);
  zonal::ShadeSettings shade{size, size, 2};
  shade.window = kRealtimeWindow;
  shade.reduced_window = kRealtimeReducedWindow;
  Reference out{zonal::shade_image(scene, basis, c, *maps, shade, &direct), {}};
  render::RenderSettings rs;
  rs.width = rs.height = size;
  out.coverage = render::object_coverage(scene, rs);
  return out;
}

std::string Realtime::reference_png(const Eigen::VectorXd& w, const std::string& env, double rotation,
                                    double exposure, int size) {
  const Reference r = reference(w, env, rotation, size);
  const ToneMap tone{ToneMap::Curve::clamp, exposure};
  std::vector<unsigned char> rgba(static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4);
  for (std::size_t p = 0; p < r.coverage.size(); ++p) {
    for (int ch = 0; ch < 3; ++ch)
      rgba[p * 4 + static_cast<std::size_t>(ch)] = tone_map_to_srgb8(r.image.rgb[p * 3 + static_cast<std::size_t>(ch)], tone);
    rgba[p * 4 + 3] = r.coverage[p] >= 1.0f ? 255 : 0;
  }
  return encode_png_srgba8(rgba.data(), size, size);
}

std::string Realtime::reference_radiance(const Eigen::VectorXd& w, const std::string& env, double rotation,
                                         double exposure, int size) {
  const Reference r = reference(w, env, rotation, size);
  const double scale = std::exp2(exposure);
  std::vector<float> rgba(r.coverage.size() * 4);
  for (std::size_t p = 0; p < r.coverage.size(); ++p) {
    for (std::size_t ch = 0; ch < 3; ++ch) rgba[p * 4 + ch] = static_cast<float>(scale * r.image.rgb[p * 3 + ch]);
    rgba[p * 4 + 3] = r.coverage[p];
  }
  return float_bytes(rgba);
}

}  // namespace matlas::server
