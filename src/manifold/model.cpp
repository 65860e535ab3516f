#include "formats/half_float.h"
#include "manifold/model.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/parallel.h"
#include "formats/merl_file.h"
#include "formats/safetensors.h"
#include "gp/convex_weights.h"
#include "manifold/dense_product.h"
#include "manifold/dot_kernel.h"
#include "manifold/model_format.h"

namespace matlas {

namespace fs = std::filesystem;
using nlohmann::json;

struct Model::Impl {
  fs::path path;
  SafetensorsFile file;
  json meta;
  std::vector<std::string> names;
  Eigen::MatrixXd latent;
  Eigen::MatrixXd albedo;  // n x (kAlbedoAngles * 3)
  Eigen::MatrixXd gram;
  MerlDims dims;
  std::size_t kept = 0;
  int n = 0;
  std::string storage;
  const float* mean = nullptr;
  std::vector<float> mean_copy;  // the mean when the map leaves it unaligned (float16 data of odd size)
  const std::int32_t* value_column = nullptr;
  const float* data_f32 = nullptr;
  const std::uint16_t* data_f16 = nullptr;
  std::unique_ptr<gp::GpPosterior> posterior;
  std::unique_ptr<gp::ConvexProjection> convex;  // the convex mode's projection
  Interpolation interpolation = Interpolation::gp;  // the mode the model was built with

  // Model::open's steps, in order; each throws matlas::Error naming the file and the problem.
  /// The metadata: format, version, names, grid, storage, counts; returns the kernel.
  gp::Kernel read_metadata();
  /// The tensors (latent, Gram, albedo, mean, column map, data), shapes checked, finite.
  void read_tensors();
  /// The small tensors' checksum and the column map's consistency with the data.
  void check_integrity() const;
  /// The GP posterior and the convex projection of the interpolation modes.
  void build_interpolation(const gp::Kernel& kernel);

  /// sum_i w_i z_i[column] over the stored inputs.
  double data_dot(std::size_t column, const Eigen::Ref<const Eigen::VectorXd>& w) const {
    const std::size_t base = column * static_cast<std::size_t>(n);
    if (data_f32) return dot_f32_f64(data_f32 + base, w.data(), n);
    const std::uint16_t* row = data_f16 + base;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += w[i] * static_cast<double>(half_to_float(row[i]));
    return sum;
  }
};

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd read_matrix(const SafetensorsFile& f, const char* name, std::int64_t rows,
                            std::int64_t cols) {
  const auto v = f.view<double>(name, DType::F64, {rows, cols});
  return Eigen::Map<const RowMajor>(v.data(), rows, cols);
}


/// An integer metadata value as text, whatever its size (for messages).
std::string integer_text(const json& v) {
  if (v.is_number_unsigned()) return std::to_string(v.get<std::uint64_t>());
  if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
  return std::string("a ") + v.type_name();
}

/// meta[key] as an integer in [lo, hi]; throws naming the field otherwise.
std::int64_t metadata_integer(const fs::path& path, const json& meta, const char* key, std::int64_t lo,
                              std::int64_t hi) {
  const auto it = meta.find(key);
  if (it == meta.end()) throw file_error(path, std::string("corrupted model metadata: missing field '") + key + "'");
  if (!it->is_number_integer())
    throw file_error(path, std::string("corrupted model metadata: '") + key + "' is not an integer");
  if (it->is_number_unsigned() ? it->get<std::uint64_t>() > static_cast<std::uint64_t>(hi)
                               : it->get<std::int64_t>() < lo || it->get<std::int64_t>() > hi)
    throw file_error(path, std::string("corrupted model metadata: '") + key + "' = " + integer_text(*it) +
                               " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return it->get<std::int64_t>();
}

/// meta[key][sub] as a finite number > 0.
double metadata_positive(const fs::path& path, const json& meta, const char* key, const char* sub) {
  const auto it = meta.find(key);
  if (it == meta.end() || !it->is_object())
    throw file_error(path, std::string("corrupted model metadata: missing or invalid '") + key + "'");
  const auto v = it->find(sub);
  if (v == it->end() || !v->is_number() || !std::isfinite(v->get<double>()) || !(v->get<double>() > 0))
    throw file_error(path, std::string("corrupted model metadata: '") + key + "." + sub +
                               "' must be a finite positive number");
  return v->get<double>();
}

template <class Derived>
void require_finite(const fs::path& path, const Eigen::DenseBase<Derived>& m, const char* tensor) {
  if (!m.allFinite())
    throw file_error(path, std::string("corrupted model: tensor '") + tensor + "' holds NaN or infinite values");
}

}  // namespace

Model::Model(std::shared_ptr<const Impl> impl, Interpolation mode) : impl_(std::move(impl)), interpolation_(mode) {}
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
Model::~Model() = default;

Model Model::open(const fs::path& path) {
  auto m = std::make_unique<Impl>(Impl{path, SafetensorsFile::open(path), {}, {}, {}, {}, {}, {}, 0, 0,
                                       {}, nullptr, {}, nullptr, nullptr, nullptr, nullptr, nullptr,
                                       Interpolation::gp});
  const gp::Kernel kernel = m->read_metadata();
  m->read_tensors();
  m->check_integrity();
  m->build_interpolation(kernel);
  const Interpolation built = m->interpolation;
  return Model(std::move(m), built);
}

gp::Kernel Model::Impl::read_metadata() {
  const SafetensorsFile& f = file;
  const auto meta_it = f.metadata().find(model_format::kMetadataKey);
  if (meta_it == f.metadata().end())
    throw file_error(path, "not a matlas model (a safetensors file without matlas metadata)");
  // Every metadata field is checked for presence, type and range here, and against the tensors
  // below: a crafted or damaged file is refused naming what is wrong, never used.
  gp::Kernel kernel{0.0, 0.0};
  try {
    // Parsing is iterative, but dump() and other recursive code would overflow the stack on a
    // crafted file nested 100,000 deep: refused here, before anything uses it.
    const json::parser_callback_t limit_depth = [&model_path = path](int depth, json::parse_event_t event, json&) {
      if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
          depth >= model_format::kMaxMetadataDepth)
        throw file_error(model_path, "corrupted model metadata: JSON nested more than " +
                                   std::to_string(model_format::kMaxMetadataDepth) + " levels deep");
      return true;
    };
    meta = json::parse(meta_it->second, limit_depth);
    if (!meta.is_object()) throw file_error(path, "corrupted model metadata: not a JSON object");
    const auto format = meta.find("format");
    if (format == meta.end() || !format->is_string() || format->get<std::string>() != model_format::kFormatName)
      throw file_error(path, "not a matlas model");
    const auto version = metadata_integer(path, meta, "format_version", std::numeric_limits<std::int64_t>::min(),
                                          std::numeric_limits<std::int64_t>::max());
    if (version != model_format::kVersion)
      throw file_error(path, "model format version " + integer_text(meta["format_version"]) +
                                 " is not supported by this matlas (expects " +
                                 std::to_string(model_format::kVersion) + "); rebuild the model");
    const auto names_json = meta.find("names");
    if (names_json == meta.end() || !names_json->is_array() || names_json->empty())
      throw file_error(path, "corrupted model metadata: 'names' must be a non-empty array of strings");
    for (const auto& name : *names_json) {
      if (!name.is_string()) throw file_error(path, "corrupted model metadata: 'names' must hold strings");
      names.push_back(name.get<std::string>());
    }
    const auto grid = meta.find("grid");
    if (grid == meta.end() || !grid->is_array() || grid->size() != 3)
      throw file_error(path, "corrupted model metadata: 'grid' must be three bin counts");
    int bins[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const json& d = (*grid)[k];
      if (!d.is_number_integer() || d.get<std::int64_t>() < 1 || d.get<std::int64_t>() > kMaxMerlDim ||
          (d.is_number_unsigned() && d.get<std::uint64_t>() > static_cast<std::uint64_t>(kMaxMerlDim)))
        throw file_error(path, "corrupted model metadata: 'grid' entries must be integers in [1, " +
                                   std::to_string(kMaxMerlDim) + "]");
      bins[k] = static_cast<int>(d.get<std::int64_t>());
    }
    if (!model_format::is_model_grid(bins[0], bins[1], bins[2]))
      throw file_error(path, "corrupted model metadata: 'grid' [" + std::to_string(bins[0]) + ", " +
                                 std::to_string(bins[1]) + ", " + std::to_string(bins[2]) +
                                 "] is not [theta_h, theta_d, phi_d] with phi_d = 2 theta_d");
    dims = {bins[0], bins[1], bins[2]};
    const auto storage_json = meta.find("storage");
    if (storage_json == meta.end() || !storage_json->is_string())
      throw file_error(path, "corrupted model metadata: missing 'storage'");
    storage = storage_json->get<std::string>();
    kernel.lengthscale = metadata_positive(path, meta, "kernel", "lengthscale");
    kernel.nugget = metadata_positive(path, meta, "kernel", "nugget");
    if (meta.contains("count") &&
        metadata_integer(path, meta, "count", 1, 1 << 30) != static_cast<std::int64_t>(names.size()))
      throw file_error(path, "corrupted model metadata: 'count' differs from the number of names");
  } catch (const json::exception& e) {
    throw file_error(path, std::string("corrupted model metadata: ") + e.what());
  }
  return kernel;
}

void Model::Impl::read_tensors() {
  const SafetensorsFile& f = file;
  n = static_cast<int>(names.size());
  const auto rows = static_cast<std::int64_t>(n);  // the inputs: rows of the small tensors
  const TensorInfo* latent_info = f.find(model_format::kLatent);
  if (!latent_info || latent_info->shape.size() != 2 || latent_info->shape[0] != rows || latent_info->shape[1] < 1 ||
      latent_info->shape[1] > 64)
    throw file_error(path, "corrupted model: latent tensor missing or of the wrong shape (expected [" +
                               std::to_string(rows) + ", q], 1 <= q <= 64)");
  const std::int64_t q = latent_info->shape[1];
  if (meta.contains("dim") && metadata_integer(path, meta, "dim", 1, 64) != q)
    throw file_error(path, "corrupted model metadata: 'dim' differs from the latent tensor's shape");
  latent = read_matrix(f, model_format::kLatent, rows, q);
  gram = read_matrix(f, model_format::kGram, rows, rows);
  albedo = Eigen::Map<const RowMajor>(
      f.view<double>(model_format::kAlbedo, DType::F64, {rows, kAlbedoAngles, 3}).data(), rows,
      kAlbedoAngles * 3);
  require_finite(path, latent, model_format::kLatent);
  require_finite(path, gram, model_format::kGram);
  require_finite(path, albedo, model_format::kAlbedo);
  const TensorInfo& mean_info = f.require(model_format::kMean, DType::F32);
  if (mean_info.shape.size() != 1) throw file_error(path, "corrupted model: mean tensor shape");
  kept = static_cast<std::size_t>(mean_info.shape[0]);
  if (kept == 0) throw file_error(path, "corrupted model: no kept columns");
  if (meta.contains("kept_columns") &&
      metadata_integer(path, meta, "kept_columns", 0, std::numeric_limits<std::int64_t>::max()) !=
          static_cast<std::int64_t>(kept))
    throw file_error(path, "corrupted model metadata: 'kept_columns' differs from the mean tensor's length");
  const std::byte* mean_bytes = f.bytes(mean_info);
  if (reinterpret_cast<std::uintptr_t>(mean_bytes) % alignof(float) == 0) {
    mean = reinterpret_cast<const float*>(mean_bytes);
  } else {
    mean_copy.resize(kept);
    std::memcpy(mean_copy.data(), mean_bytes, kept * sizeof(float));
    mean = mean_copy.data();
  }
  require_finite(path, Eigen::Map<const Eigen::VectorXf>(mean, static_cast<Eigen::Index>(kept)),
                 model_format::kMean);
  const auto columns = f.view<std::int32_t>(model_format::kValueColumn, DType::I32,
                                            {static_cast<std::int64_t>(3 * dims.bins())});
  value_column = columns.data();
  const auto d = static_cast<std::int64_t>(kept);
  if (storage == "F32")
    data_f32 = f.view<float>(model_format::kData, DType::F32, {d, rows}).data();
  else if (storage == "F16")
    data_f16 = f.view<std::uint16_t>(model_format::kData, DType::F16, {d, rows}).data();
  else
    throw file_error(path, "corrupted model: unknown storage '" + storage + "'");
}

void Model::Impl::check_integrity() const {
  const SafetensorsFile& f = file;
  const bool has_layout_gram = f.find(model_format::kLayoutGram) != nullptr;
  const auto columns = std::span<const std::int32_t>(value_column, static_cast<std::size_t>(3 * dims.bins()));
  const auto d = static_cast<std::int64_t>(kept);
  // Integrity of everything but the bulk data: checksum, and the column map's consistency.
  Xxh3Hasher h;
  for (const char* name : {model_format::kLatent, model_format::kGram, model_format::kAlbedo,
                           model_format::kMean, model_format::kValueColumn, model_format::kLayoutGram}) {
    if (std::string_view(name) == model_format::kLayoutGram && !has_layout_gram) continue;  // optional (older models)
    const TensorInfo* t = f.find(name);
    if (!t) throw file_error(path, std::string("corrupted model: missing tensor '") + name + "'");
    h.update(f.bytes(*t), t->bytes());
  }
  const std::string checksum = hex64(h.digest());
  const auto stored_checksum = meta.find("small_tensors_xxh3_64");
  if (stored_checksum == meta.end() || !stored_checksum->is_string() ||
      checksum != stored_checksum->get<std::string>())
    throw file_error(path, "corrupted model: checksum mismatch in the latent/mean/column tensors");
  // The column map: kept columns numbered 0, 1, ... in value order, every other entry exactly -1
  // (dropped), and as many kept columns as the data has rows.
  std::int64_t next = 0;
  for (std::size_t v = 0; v < columns.size(); ++v) {
    if (columns[v] < -1 || (columns[v] >= 0 && columns[v] != next++))
      throw file_error(path, "corrupted model: inconsistent column map");
  }
  if (next != d) throw file_error(path, "corrupted model: column map does not match the data");
}

void Model::Impl::build_interpolation(const gp::Kernel& kernel) {
  const SafetensorsFile& f = file;
  const bool has_layout_gram = f.find(model_format::kLayoutGram) != nullptr;
  try {
    posterior = std::make_unique<gp::GpPosterior>(latent, kernel);
  } catch (const Error& e) {
    throw file_error(path, std::string("corrupted model: ") + e.what());
  }

  // Interpolation mode: "interpolation": {"mode": "convex", "ridge": r} (absent: the paper's GP).
  double ridge = gp::ConvexProjection::kDefaultRidge;
  try {
    if (const auto it = meta.find("interpolation"); it != meta.end()) {
      interpolation = interpolation_from_string(it->at("mode").get<std::string>());
      ridge = it->value("ridge", ridge);
    }
  } catch (const json::exception& e) {
    throw file_error(path, std::string("corrupted model metadata (interpolation): ") + e.what());
  } catch (const Error& e) {
    throw file_error(path, std::string("corrupted model metadata: ") + e.what());
  }
  try {
    const Eigen::MatrixXd metric = has_layout_gram ? read_matrix(f, model_format::kLayoutGram, n, n) : gram;
    convex = std::make_unique<gp::ConvexProjection>(metric, ridge);
  } catch (const Error& e) {
    throw file_error(path, std::string("corrupted model: ") + e.what());
  }
}

const fs::path& Model::path() const { return impl_->path; }
int Model::count() const { return impl_->n; }
int Model::dim() const { return static_cast<int>(impl_->latent.cols()); }
const std::vector<std::string>& Model::names() const { return impl_->names; }
const Eigen::MatrixXd& Model::latent() const { return impl_->latent; }
const MerlDims& Model::dims() const { return impl_->dims; }
std::size_t Model::kept_columns() const { return impl_->kept; }
const gp::GpPosterior& Model::posterior() const { return *impl_->posterior; }
const nlohmann::json& Model::metadata() const { return impl_->meta; }
const Eigen::MatrixXd& Model::gram() const { return impl_->gram; }
const Eigen::MatrixXd& Model::convex_metric() const { return impl_->convex->metric(); }
const Eigen::MatrixXd& Model::material_albedo() const { return impl_->albedo; }
const std::string& Model::storage() const { return impl_->storage; }

Model::FileState Model::file_state() const {
  switch (impl_->file.mapping().disk_state()) {
    case MappedFile::DiskState::same: return FileState::same;
    case MappedFile::DiskState::modified: return FileState::modified;
    case MappedFile::DiskState::replaced: break;
  }
  return FileState::replaced;
}

std::uint64_t Model::mapping_faults() const { return impl_->file.mapping().faults(); }
int Model::index_of(const std::string& name) const {
  const auto& names = impl_->names;
  const auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return static_cast<int>(it - names.begin());
  std::string close;
  for (const auto& candidate : names)
    if (candidate.find(name) != std::string::npos || name.find(candidate) != std::string::npos)
      close += (close.empty() ? "" : ", ") + candidate;
  throw Error("no material named '" + name + "' in " + impl_->path.string() +
              (close.empty() ? " (see `matlas latent MODEL` for the names)" : "; did you mean: " + close + "?"));
}

Eigen::VectorXd Model::latent_min() const { return impl_->latent.colwise().minCoeff().transpose(); }
Eigen::VectorXd Model::latent_max() const { return impl_->latent.colwise().maxCoeff().transpose(); }
Interpolation Model::interpolation() const { return interpolation_; }
Model Model::with_interpolation(Interpolation mode) const { return Model(impl_, mode); }
Eigen::VectorXd Model::weights_from_gp(const Eigen::Ref<const Eigen::VectorXd>& w, Interpolation mode) const {
  MATLAS_CHECK_EQ(w.size(), Eigen::Index{count()});
  return mode == Interpolation::gp ? Eigen::VectorXd(w) : impl_->convex->from_centred(w);
}
Eigen::VectorXd Model::weights_from_gp(const Eigen::Ref<const Eigen::VectorXd>& w) const { return weights_from_gp(w, interpolation_); }

void Model::check_point(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (x.size() != dim())
    throw Error("latent point has " + std::to_string(x.size()) + " coordinates, the model has q = " +
                std::to_string(dim()));
  if (!x.allFinite()) throw Error("latent point has a NaN or infinite coordinate");
}
Eigen::VectorXd Model::weights(const Eigen::Ref<const Eigen::VectorXd>& x, Interpolation mode) const {
  check_point(x);
  return weights_from_gp(impl_->posterior->weights(x), mode);
}
Eigen::VectorXd Model::weights(const Eigen::Ref<const Eigen::VectorXd>& x) const { return weights(x, interpolation_); }
Eigen::VectorXd Model::weights(const Eigen::Ref<const Eigen::VectorXd>& x, WarmStart& warm) const {
  if (interpolation_ != Interpolation::convex) return weights(x);
  check_point(x);
  return impl_->convex->from_centred(impl_->posterior->weights(x), warm);
}

Model::Prediction Model::predict_batch(const Eigen::MatrixXd& points) const { return predict_batch(points, interpolation_); }
Model::Prediction Model::predict_batch(const Eigen::MatrixXd& points, Interpolation mode) const {
  if (points.cols() != dim())
    throw Error("latent points have " + std::to_string(points.cols()) + " coordinates, the model has q = " +
                std::to_string(dim()));
  if (!points.allFinite()) throw Error("latent point has a NaN or infinite coordinate");
  gp::GpPosterior::Batch b = impl_->posterior->predict_batch(points);
  weights_from_gp_batch(b.weights, mode);
  return {std::move(b.weights), std::move(b.variance)};
}
Model::Prediction Model::predict_grid(const Eigen::VectorXd& origin, const Eigen::VectorXd& axis_u,
                                     const Eigen::VectorXd& axis_v, const Eigen::VectorXd& u, const Eigen::VectorXd& v) const {
  gp::GpPosterior::Batch b = impl_->posterior->predict_grid({origin, axis_u, axis_v, u, v});
  return {std::move(b.weights), std::move(b.variance)};
}
void Model::weights_from_gp_batch(Eigen::Ref<Eigen::MatrixXd> W, Interpolation mode) const {
  MATLAS_CHECK_EQ(W.rows(), Eigen::Index{count()});
  if (mode != Interpolation::convex) return;
  // Each column's solve starts from the previous column's solution, in one run per worker
  // (gp/convex_weights.h, project_batch): fastest when consecutive columns are neighbours.
  const auto workers = static_cast<Eigen::Index>(std::max(1u, worker_count()));
  impl_->convex->from_centred_batch(W, (W.cols() + workers - 1) / workers);
}

Eigen::VectorXd Model::material_weights(int i) const {
  if (i < 0 || i >= count()) throw Error("material index out of range: " + std::to_string(i));
  return Eigen::VectorXd::Unit(count(), i);
}
double Model::variance(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  check_point(x);
  return impl_->posterior->variance(x);
}
bool Model::kept(std::size_t v) const { return impl_->value_column[v] >= 0; }
int Model::column_of(std::size_t v) const { return impl_->value_column[v]; }
float Model::mean(std::size_t column) const { return impl_->mean[column]; }
const float* Model::data_f32(std::size_t column) const {
  return impl_->data_f32 ? impl_->data_f32 + column * static_cast<std::size_t>(impl_->n) : nullptr;
}
void Model::data(std::size_t column, float* out) const {
  const std::size_t base = column * static_cast<std::size_t>(impl_->n);
  for (int i = 0; i < impl_->n; ++i)
    out[i] = impl_->data_f32 ? impl_->data_f32[base + static_cast<std::size_t>(i)]
                             : half_to_float(impl_->data_f16[base + static_cast<std::size_t>(i)]);
}

double Model::value(std::size_t v, const Eigen::Ref<const Eigen::VectorXd>& w) const {
  const std::int32_t c = impl_->value_column[v];
  if (c < 0) return std::numeric_limits<double>::quiet_NaN();
  // mean + sum_i w_i (z_i - mean), written so that w = e_i returns z_i exactly.
  return Combination::mean_weight(w) * impl_->mean[c] + impl_->data_dot(static_cast<std::size_t>(c), w);
}

Rgb Model::bin_rgb(std::size_t bin, const Eigen::Ref<const Eigen::VectorXd>& w) const {
  Rgb rgb;
  const std::size_t bins = impl_->dims.bins();
  for (int c = 0; c < 3; ++c) {
    const double v = value(static_cast<std::size_t>(c) * bins + bin, w);
    rgb[c] = std::isnan(v) ? 0.0 : v;
  }
  return rgb;
}

Rgb Model::lookup(const Vec3& wi, const Vec3& wo, const Eigen::Ref<const Eigen::VectorXd>& w) const {
  return bin_rgb(bin_of(impl_->dims, wi, wo), w);
}

BrdfTable Model::table(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  if (w.size() != count()) throw Error("weight vector has the wrong length");
  BrdfTable t(impl_->dims, ValueBuffer::Uninitialized{});
  const std::size_t bins = impl_->dims.bins();
  const double weight_of_mean = Combination::mean_weight(w);
  // Convex weights have a few non-zero entries: then only their values are read (a few cache
  // lines of each column's n instead of all; the same sums, in the same order, as data_dot).
  std::vector<int> nonzero;
  for (int i = 0; i < count(); ++i)
    if (w[i] != 0.0) nonzero.push_back(i);
  const bool sparse = nonzero.size() * 4 <= static_cast<std::size_t>(count());
  const auto n = static_cast<std::size_t>(count());
  parallel_for(0, t.size(), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t v = lo; v < hi; ++v) {
      const auto channel = static_cast<int>(v / bins);
      const std::int32_t c = impl_->value_column[v];
      if (c < 0) {
        t.set_missing(channel, v % bins);
        continue;
      }
      const auto column = static_cast<std::size_t>(c);
      double dot = 0.0;
      if (!sparse) {
        dot = impl_->data_dot(column, w);
      } else if (impl_->data_f32) {
        const float* row = impl_->data_f32 + column * n;
        for (const int i : nonzero) dot += w[i] * static_cast<double>(row[i]);
      } else {
        const std::uint16_t* row = impl_->data_f16 + column * n;
        for (const int i : nonzero) dot += w[i] * static_cast<double>(half_to_float(row[i]));
      }
      t.set_value(channel, v % bins, weight_of_mean * impl_->mean[column] + dot);
    }
  }, 65536);
  return t;
}

std::vector<Rgb> Model::albedo_curve(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  MATLAS_CHECK_EQ(w.size(), Eigen::Index{count()});
  const Eigen::RowVectorXd mean = impl_->albedo.colwise().mean();
  const Eigen::RowVectorXd a = mean + w.transpose() * (impl_->albedo.rowwise() - mean);
  std::vector<Rgb> curve(kAlbedoAngles);
  for (int t = 0; t < kAlbedoAngles; ++t) curve[static_cast<std::size_t>(t)] = Rgb(a[3 * t], a[3 * t + 1], a[3 * t + 2]);
  return curve;
}

Eigen::MatrixXd Model::albedo_batch(const Eigen::MatrixXd& W) const {
  MATLAS_CHECK_EQ(W.rows(), Eigen::Index{count()});
  const Eigen::RowVectorXd mean = impl_->albedo.colwise().mean();
  Eigen::MatrixXd a = blas_product((impl_->albedo.rowwise() - mean).transpose(), W);
  a.colwise() += mean.transpose();
  return a;
}

}  // namespace matlas
