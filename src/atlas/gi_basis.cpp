#include "atlas/gi_basis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "atlas/gi_density.h"
#include "atlas/model_bank.h"
#include "atlas/model_basis.h"
#include "core/check.h"
#include "core/error.h"
#include "formats/safetensors.h"

namespace matlas::atlas {

namespace {

Error file_error(const std::filesystem::path& path, const std::string& what) {
  return Error(path.string() + ": " + what);
}

bool all_finite(const float* v, std::size_t n) {
  bool ok = true;
  for (std::size_t i = 0; i < n; ++i) ok &= std::isfinite(v[i]);
  return ok;
}

/// A material's images must be finite: GiBasis::load refuses NaN and infinite pixels, so a basis
/// holding them must never be written (nor cached). They come from BRDF values so large that
/// products along paths touching the object several times overflow float32 (3.4e38).
void require_finite_images(const Model& model, int k, const Image& linear, const Image& full) {
  if (all_finite(linear.rgb.data(), linear.rgb.size()) && all_finite(full.rgb.data(), full.rgb.size())) return;
  const std::string what = k == 0 ? std::string("the mean table")
                                  : "material '" + model.names()[static_cast<std::size_t>(k - 1)] + "'";
  throw file_error(model.path(), what + " gives NaN or infinite pixels in the GI basis (its values are so large that "
                                        "light bouncing on the object several times overflows float32): a basis "
                                        "with them could not be read, none is written");
}

std::filesystem::path material_file(const std::filesystem::path& cache, int k) {
  char name[48];
  std::snprintf(name, sizeof name, "material-%04d.safetensors", k);
  return cache / name;
}

void write_images(const std::filesystem::path& path, const std::string& key,
                  const std::vector<std::pair<std::string, const Image*>>& images) {
  SafetensorsWriter w;
  w.add_metadata("key", key);
  for (const auto& [name, im] : images) w.declare(name, DType::F32, {im->height, im->width, 3});
  w.begin(path);
  for (const auto& [name, im] : images) w.write(std::span<const float>(im->rgb));
  w.commit();
}

/// The named images of a cache file when it exists with this key and size, else false.
bool read_images(const std::filesystem::path& path, const std::string& key, int width, int height,
                 const std::vector<std::pair<std::string, Image*>>& images) {
  if (!std::filesystem::exists(path)) return false;
  try {
    const SafetensorsFile f = SafetensorsFile::open(path);
    const auto it = f.metadata().find("key");
    if (it == f.metadata().end() || it->second != key) return false;
    for (const auto& [name, im] : images) {
      const auto v = f.view<float>(name, DType::F32, {height, width, 3});
      if (!all_finite(v.data(), v.size())) return false;  // traced again (and refused there)
      *im = Image(width, height);
      std::copy(v.begin(), v.end(), im->rgb.begin());
    }
    return true;
  } catch (const Error&) {
    return false;  // a damaged cache entry is traced again
  }
}

}  // namespace

GiBasis::GiBasis(Image p, const std::vector<Image>& linear, const std::vector<Image>& full,
                 std::vector<std::string> names, std::map<std::string, std::string> metadata)
    : p_(std::move(p)), names_(std::move(names)), metadata_(std::move(metadata)) {
  if (names_.empty()) throw Error("GI basis: no materials");
  if (linear.size() != names_.size() + 1 || full.size() != linear.size())
    throw Error("GI basis: expected n + 1 images per part for n names");
  for (std::size_t k = 0; k < linear.size(); ++k)
    if (linear[k].width != p_.width || linear[k].height != p_.height || full[k].width != p_.width ||
        full[k].height != p_.height)
      throw Error("GI basis: images of different sizes");
  MATLAS_CHECK(p_.rgb.size() == 3 * p_.pixel_count(), "an RGB image");
  // Each part: its mean image X_0, the material images X_1..X_n and P as the offset.
  linear_ = render::ImageBasis(linear[0], std::span(linear).subspan(1));
  full_ = render::ImageBasis(full[0], std::span(full).subspan(1));
  linear_.set_offset(p_);
  full_.set_offset(p_);
}

double GiBasis::convert_to_half() { return std::max(linear_.convert_to_half(), full_.convert_to_half()); }

Image GiBasis::image(Part which, int k) const {
  MATLAS_CHECK(k >= 0 && static_cast<std::size_t>(k) <= names_.size(), "image index in 0..n (the mean and n materials)");
  return k == 0 ? part(which).mean_image() : part(which).material_image(k - 1);
}

Image GiBasis::compose(const Eigen::Ref<const Eigen::VectorXd>& w, Part which) const {
  Image out(width(), height());
  compose(w, which, out.rgb.data());
  return out;
}

void GiBasis::compose(const Eigen::Ref<const Eigen::VectorXd>& w, Part which, float* rgb) const {
  if (w.size() != count()) throw Error("GI basis: weights of length " + std::to_string(w.size()) + " for " +
                                       std::to_string(count()) + " materials");
  part(which).compose(w, rgb);  // P + sum_k a_k X_k, a = (1 - sum w, w)
}

void GiBasis::save(const std::filesystem::path& path) const {
  // load() refuses NaN and infinite pixels: such a basis is not written (the file appears only at
  // commit, so a bad image met while writing leaves nothing).
  const auto refuse = [&] {
    throw file_error(path, "the GI basis has NaN or infinite pixels: not written (it could not be read back)");
  };
  if (!all_finite(p_.rgb.data(), p_.rgb.size())) refuse();
  const std::int64_t k = count() + 1, h = height(), wd = width();
  SafetensorsWriter w;
  for (const auto& [key, value] : metadata_) w.add_metadata(key, value);
  w.add_metadata("format", "matlas-gi-basis");
  w.add_metadata("names", nlohmann::json(names_).dump());
  w.declare("p", DType::F32, {h, wd, 3});
  w.declare("linear", DType::F32, {k, h, wd, 3});
  w.declare("full", DType::F32, {k, h, wd, 3});
  w.begin(path);
  w.write(std::span<const float>(p_.rgb));
  for (const Part which : {Part::i1, Part::all})
    for (int i = 0; i < k; ++i) {  // one image in memory at a time
      const Image im = image(which, i);
      if (!all_finite(im.rgb.data(), im.rgb.size())) refuse();
      w.write(std::span<const float>(im.rgb));
    }
  w.commit();
}

GiBasis GiBasis::load(const std::filesystem::path& path) {
  const SafetensorsFile f = SafetensorsFile::open(path);
  const auto& meta = f.metadata();
  const auto format = meta.find("format");
  if (format == meta.end() || format->second != "matlas-gi-basis") throw file_error(path, "not a matlas GI basis");
  std::vector<std::string> names;
  try {
    names = nlohmann::json::parse(meta.at("names")).get<std::vector<std::string>>();
  } catch (const std::exception&) {
    throw file_error(path, "bad \"names\" metadata");
  }
  if (names.empty()) throw file_error(path, "a GI basis of no materials");
  const TensorInfo& pt = f.require("p", DType::F32);
  if (pt.shape.size() != 3 || pt.shape[2] != 3 || pt.shape[0] <= 0 || pt.shape[1] <= 0)
    throw file_error(path, "tensor p is not [H, W, 3]");
  const std::int64_t h = pt.shape[0], wd = pt.shape[1], k = static_cast<std::int64_t>(names.size()) + 1;
  const auto p = f.view<float>("p", DType::F32, {h, wd, 3});
  const auto linear = f.view<float>("linear", DType::F32, {k, h, wd, 3});
  const auto full = f.view<float>("full", DType::F32, {k, h, wd, 3});
  for (const auto& span : {p, linear, full})
    if (!all_finite(span.data(), span.size())) throw file_error(path, "GI basis has NaN or infinite pixels");
  Image pi(static_cast<int>(wd), static_cast<int>(h));
  std::copy(p.begin(), p.end(), pi.rgb.begin());
  std::vector<Image> l, fu;
  const std::size_t values = pi.rgb.size();
  for (std::int64_t i = 0; i < k; ++i) {
    l.emplace_back(pi.width, pi.height);
    fu.emplace_back(pi.width, pi.height);
    std::copy_n(linear.data() + static_cast<std::size_t>(i) * values, values, l.back().rgb.begin());
    std::copy_n(full.data() + static_cast<std::size_t>(i) * values, values, fu.back().rgb.begin());
  }
  std::map<std::string, std::string> kept(meta.begin(), meta.end());
  kept.erase("names");
  kept.erase("format");
  return GiBasis(std::move(pi), l, fu, std::move(names), std::move(kept));
}

std::string gi_basis_key(const Model& model, const pathtrace::World& world, const pathtrace::TraceSettings& s) {
  const nlohmann::json key = {{"model_fingerprint", model_fingerprint(model)},
                              {"scene", pathtrace::scene_to_json(world.spec())},
                              {"width", s.width}, {"height", s.height}, {"spp", s.spp}, {"seed", s.seed},
                              {"max_depth", s.max_depth}, {"roulette_depth", s.roulette_depth},
                              {"mirror_probability", s.mirror_probability},
                              {"density", density_record(s.density)}};
  return key.dump();
}

GiBasis build_gi_basis(const Model& model, const pathtrace::World& world, const pathtrace::TraceSettings& settings,
                       const GiBasisOptions& options, ProgressSink& progress, Communicator& comm) {
  settings.validate();
  if (world.measured_object() < 0) throw Error("scene '" + world.spec().name + "' has no measured object");
  if (options.batch <= 0) throw Error("batch must be positive");
  const std::string key = gi_basis_key(model, world, settings);
  const int k_count = model.count() + 1, w = settings.width, h = settings.height;
  const bool cached = !options.cache.empty();
  // This rank traces a contiguous share of the batches, materials [mine_first, mine_last) (rank 0
  // the first: the mean, and P): the paths do not depend on the batch, so its images are those of
  // a single process, and the batches (each a full set of paths) are not cut into more.
  const int batches = (k_count + options.batch - 1) / options.batch;
  const auto share = share_of(static_cast<std::size_t>(batches), comm.rank(), comm.size());
  const int mine_first = std::min(k_count, static_cast<int>(share.first) * options.batch);
  const int mine_last = std::min(k_count, static_cast<int>(share.second) * options.batch);
  Image p;
  std::vector<Image> linear(static_cast<std::size_t>(mine_last - mine_first)), full(linear.size());
  bool have_p = !comm.is_root();  // only rank 0 keeps P
  int reused = 0;
  run_collectively(comm, [&] {
    if (cached) std::filesystem::create_directories(options.cache);
    if (!have_p) have_p = cached && read_images(options.cache / "p.safetensors", key, w, h, {{"p", &p}});
    for (int first = mine_first; first < mine_last; first += options.batch) {
      const int last = std::min(mine_last, first + options.batch);
      auto at = [&](int k) { return static_cast<std::size_t>(k - mine_first); };
      bool all_cached = cached;
      for (int k = first; k < last && all_cached; ++k)
        all_cached = read_images(material_file(options.cache, k), key, w, h, {{"linear", &linear[at(k)]}, {"full", &full[at(k)]}});
      if (all_cached) {
        reused += last - first;
        continue;
      }
      progress.message("tracing materials " + std::to_string(first) + ".." + std::to_string(last - 1) + " of " +
                       std::to_string(k_count - 1) + " (0: the mean)");
      const ModelBank bank(model, first, last);
      pathtrace::TraceImages r = pathtrace::trace(world, &bank, settings, progress);
      for (int k = first; k < last; ++k) {
        const std::size_t j = static_cast<std::size_t>(k - first);
        linear[at(k)] = r.once[j];
        full[at(k)] = r.once[j];
        for (std::size_t v = 0; v < r.more[j].rgb.size(); ++v) full[at(k)].rgb[v] += r.more[j].rgb[v];
        require_finite_images(model, k, linear[at(k)], full[at(k)]);
        if (cached) write_images(material_file(options.cache, k), key, {{"linear", &linear[at(k)]}, {"full", &full[at(k)]}});
      }
      if (!have_p) {
        p = std::move(r.p);
        have_p = true;
        if (cached) write_images(options.cache / "p.safetensors", key, {{"p", &p}});
      }
    }
    if (!have_p) {  // every material came from the cache but P did not
      const ModelBank bank(model, 0, 1);
      p = pathtrace::trace(world, &bank, settings, progress).p;
      if (cached) write_images(options.cache / "p.safetensors", key, {{"p", &p}});
    }
  });
  linear = gather_images(std::move(linear), comm);
  full = gather_images(std::move(full), comm);
  if (!comm.is_root()) return {};
  if (reused > 0) progress.message("reused " + std::to_string(reused) + " cached material images");
  std::map<std::string, std::string> meta;
  meta["key"] = key;
  meta["model"] = model.path().filename().string();
  meta["model_fingerprint"] = model_fingerprint(model);
  meta["scene"] = pathtrace::scene_to_json(world.spec()).dump();
  meta["spp"] = std::to_string(settings.spp);
  meta["seed"] = std::to_string(settings.seed);
  meta["density"] = density_record(settings.density);
  meta["i2"] = "interpolated with the map's weights from the inputs' and the mean's I2 images";
  return GiBasis(std::move(p), linear, full, model.names(), std::move(meta));
}

void require_basis_of_model(const GiBasis& basis, const Model& model, const std::filesystem::path& path) {
  const auto fp = basis.metadata().find("model_fingerprint");
  if (fp == basis.metadata().end() || fp->second != model_fingerprint(model))
    throw file_error(path, "the basis was traced for another model than " + model.path().string());
}

std::string gi_basis_scene_name(const GiBasis& basis) {
  const auto it = basis.metadata().find("scene");
  if (it == basis.metadata().end()) return {};
  const nlohmann::json j = nlohmann::json::parse(it->second, nullptr, false);
  return j.is_object() && j.contains("name") && j["name"].is_string() ? j["name"].get<std::string>() : std::string();
}

GiBasis open_or_build_gi_basis(const Model& model, const pathtrace::World& world, const pathtrace::TraceSettings& settings,
                               const std::filesystem::path& path, int batch, ProgressSink& progress) {
  const std::string key = gi_basis_key(model, world, settings);
  if (std::filesystem::exists(path)) {
    try {
      GiBasis basis = GiBasis::load(path);
      const auto it = basis.metadata().find("key");
      if (it != basis.metadata().end() && it->second == key) return basis;
    } catch (const Error&) {
      // A damaged or foreign file: traced again and replaced.
    }
  }
  GiBasisOptions options;
  options.batch = batch;
  options.cache = path.string() + ".cache";
  GiBasis basis = build_gi_basis(model, world, settings, options, progress);
  basis.save(path);
  return basis;
}

}  // namespace matlas::atlas
