#include "formats/half_float.h"
#include "render/image_basis.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "core/parallel.h"
#include "formats/safetensors.h"
#include "render/basis_kernels.h"

namespace matlas::render {

using detail::accumulate_f16;
using detail::accumulate_f32;
using detail::half_table;

namespace {

constexpr const char* kFormat = "matlas-image-basis";
// Values are stored in tiles of kChunk packed floats: tile t holds rows 0..rows-1 of packed
// entries [t * kChunk, (t + 1) * kChunk), one after the other, so one tile of a composition reads
// one contiguous stretch of memory (the hardware prefetchers follow it across pages) instead of
// n short runs scattered over n rows.
constexpr std::size_t kChunk = 2048;  // packed floats per tile row (8 KiB of float32 accumulator)

std::size_t tile_count(std::size_t packed) { return (packed + kChunk - 1) / kChunk; }

/// Position of packed entry k of row `row` in tiled storage of `rows` rows.
std::size_t tiled(std::size_t row, std::size_t k, std::size_t rows) {
  return (k / kChunk) * kChunk * rows + row * kChunk + k % kChunk;
}

template <class T>
bool same_value(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

// --- construction and packing -------------------------------------------------------------------

ImageBasis::ImageBasis(Image mean, std::span<const Image> images, std::vector<std::string> names,
                       std::map<std::string, std::string> metadata)
    : width_(mean.width), height_(mean.height), n_(static_cast<int>(images.size())), names_(std::move(names)),
      metadata_(std::move(metadata)) {
  if (mean.empty()) throw Error("image basis: empty mean image");
  if (images.empty()) throw Error("image basis: no material images");
  if (!names_.empty() && names_.size() != images.size()) throw Error("image basis: names and images differ in count");
  std::vector<const float*> pointers;
  for (const Image& im : images) {
    if (im.width != width_ || im.height != height_) throw Error("image basis: images differ in size");
    pointers.push_back(im.rgb.data());
  }
  mean_ = std::move(mean.rgb);
  pack(mean_.data(), pointers);
}

void ImageBasis::pack(const float* mean, const std::vector<const float*>& images) {
  const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  MATLAS_CHECK_EQ(images.size(), static_cast<std::size_t>(n_));
  active_.clear();
  for (std::size_t p = 0; p < pixels; ++p) {
    // Inactive: every material and the mean have one value there, so any weights give it
    // (the coefficients sum to one).
    bool differs = false;
    for (std::size_t c = 0; c < 3; ++c) differs = differs || !same_value(mean[3 * p + c], images[0][3 * p + c]);
    for (std::size_t i = 1; i < images.size() && !differs; ++i)
      for (std::size_t c = 0; c < 3; ++c)
        if (!same_value(images[i][3 * p + c], images[0][3 * p + c])) differs = true;
    if (differs) active_.push_back(static_cast<std::uint32_t>(p));
  }
  packed_ = 3 * active_.size();
  packed_mean_.resize(packed_);
  values_f32_.assign(static_cast<std::size_t>(n_) * tile_count(packed_) * kChunk, 0.0f);
  values_f16_.clear();
  precision_ = BasisPrecision::f32;
  for (std::size_t a = 0; a < active_.size(); ++a)
    for (std::size_t c = 0; c < 3; ++c) {
      packed_mean_[3 * a + c] = mean[3 * active_[a] + c];
      for (std::size_t i = 0; i < images.size(); ++i)
        values_f32_[tiled(i, 3 * a + c, images.size())] = images[i][3 * active_[a] + c];
    }
  pack_offset();
  rank_ = 0;
  factors_.clear();
}

void ImageBasis::pack_offset() {
  packed_offset_.clear();
  if (offset_.empty()) return;
  packed_offset_.resize(packed_);
  for (std::size_t a = 0; a < active_.size(); ++a)
    for (std::size_t c = 0; c < 3; ++c) packed_offset_[3 * a + c] = offset_[3 * active_[a] + c];
}

void ImageBasis::set_offset(const Image& offset) {
  if (offset.width != width_ || offset.height != height_) throw Error("image basis: the offset image differs in size");
  offset_ = offset.rgb;
  pack_offset();
}

Image ImageBasis::offset_image() const {
  Image im(width_, height_);
  if (!offset_.empty()) im.rgb = offset_;
  return im;
}

double ImageBasis::active_fraction() const {
  const double pixels = static_cast<double>(width_) * static_cast<double>(height_);
  return pixels > 0 ? static_cast<double>(active_.size()) / pixels : 0.0;
}

std::size_t ImageBasis::compose_bytes() const {
  return static_cast<std::size_t>(n_) * packed_ * (precision_ == BasisPrecision::f16 ? 2 : 4);
}

double ImageBasis::convert_to_half() {
  if (precision_ == BasisPrecision::f16) return 0.0;
  values_f16_.resize(values_f32_.size());
  double err = 0, norm = 0;
  for (std::size_t k = 0; k < values_f32_.size(); ++k) {
    values_f16_[k] = float_to_half(values_f32_[k]);
    const double d = static_cast<double>(half_to_float(values_f16_[k])) - values_f32_[k];
    err += d * d;
    norm += static_cast<double>(values_f32_[k]) * values_f32_[k];
  }
  std::vector<float>().swap(values_f32_);
  precision_ = BasisPrecision::f16;
  return norm > 0 ? std::sqrt(err / norm) : 0.0;
}

void ImageBasis::unpack_into(int i, float* rgb) const {
  MATLAS_CHECK(i >= 0 && i < n_, "material index in range");
  std::copy(mean_.begin(), mean_.end(), rgb);
  const auto rows = static_cast<std::size_t>(n_);
  for (std::size_t a = 0; a < active_.size(); ++a)
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t k = tiled(static_cast<std::size_t>(i), 3 * a + c, rows);
      rgb[3 * active_[a] + c] = precision_ == BasisPrecision::f32 ? values_f32_[k] : half_to_float(values_f16_[k]);
    }
}

Image ImageBasis::mean_image() const {
  Image im(width_, height_);
  im.rgb = mean_;
  return im;
}

Image ImageBasis::material_image(int i) const {
  MATLAS_CHECK(i >= 0 && i < n_, "material index in range");
  Image im(width_, height_);
  unpack_into(i, im.rgb.data());
  return im;
}

// --- composition ------------------------------------------------------------------------------

void ImageBasis::compose_tiles(const Terms& terms, std::size_t rows, float mean_weight, const float* f32,
                               const std::uint16_t* f16, float* rgb) const {
  // rgb = offset + mean_weight * mean + sum_t weight_t * row_{index_t} on the active pixels, the
  // full-image offset + mean elsewhere. When every pixel is active the packed values are the
  // image's, written in place.
  const bool dense = active_.size() == static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  const bool offset = !offset_.empty();
  if (!dense)
    parallel_for(0, mean_.size(), [&](std::size_t v0, std::size_t v1) {
      for (std::size_t v = v0; v < v1; ++v) rgb[v] = offset ? offset_[v] + mean_[v] : mean_[v];
    }, std::size_t(1) << 16);
  const int n = static_cast<int>(terms.index.size());
  parallel_for(0, tile_count(packed_), [&](std::size_t t0, std::size_t t1) {
    alignas(64) float acc[kChunk];
    for (std::size_t t = t0; t < t1; ++t) {
      const std::size_t begin = t * kChunk, len = std::min(kChunk, packed_ - begin), base = t * kChunk * rows;
      if (offset)
        for (std::size_t j = 0; j < len; ++j) acc[j] = packed_offset_[begin + j] + mean_weight * packed_mean_[begin + j];
      else
        for (std::size_t j = 0; j < len; ++j) acc[j] = mean_weight * packed_mean_[begin + j];
      if (f16) accumulate_f16(f16 + base, kChunk, 0, len, terms.index.data(), terms.weight.data(), n, acc);
      else accumulate_f32(f32 + base, kChunk, 0, len, terms.index.data(), terms.weight.data(), n, acc);
      if (dense) {
        std::copy_n(acc, len, rgb + begin);
        continue;
      }
      for (std::size_t j = 0; j < len; ++j) {
        const std::size_t k = begin + j;
        rgb[3 * static_cast<std::size_t>(active_[k / 3]) + k % 3] = acc[j];
      }
    }
  }, 8);
}

void ImageBasis::compose(const Eigen::Ref<const Eigen::VectorXd>& w, float* rgb) const {
  MATLAS_CHECK_EQ(w.size(), n_);
  // I(w) = (1 - sum w) I_mean + sum_i w_i I_i, reading only the images of non-zero weights (convex
  // weights have a handful).
  Terms terms;
  for (int i = 0; i < n_; ++i)
    if (const auto wi = static_cast<float>(w[i]); wi != 0.0f) {
      terms.index.push_back(i);
      terms.weight.push_back(wi);
    }
  const bool half = precision_ == BasisPrecision::f16;
  compose_tiles(terms, static_cast<std::size_t>(n_), static_cast<float>(Combination::mean_weight(w)),
                half ? nullptr : values_f32_.data(), half ? values_f16_.data() : nullptr, rgb);
}

Image ImageBasis::compose(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  Image im(width_, height_);
  compose(w, im.rgb.data());
  return im;
}

void ImageBasis::compose_fast(const Eigen::Ref<const Eigen::VectorXd>& w, float* rgb) const {
  // The exact form reads one image per non-zero weight, the low-rank form rank_ factors: with
  // no more non-zero weights than that (convex weights have a handful) the exact one is cheaper.
  if (rank_ == 0 || (w.array() != 0.0).count() <= rank_) return compose(w, rgb);
  compose_low_rank(w, rgb);
}

Image ImageBasis::compose_fast(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  Image im(width_, height_);
  compose_fast(w, im.rgb.data());
  return im;
}

void ImageBasis::compose_low_rank(const Eigen::Ref<const Eigen::VectorXd>& w, float* rgb) const {
  if (rank_ == 0) return compose(w, rgb);
  MATLAS_CHECK_EQ(w.size(), n_);
  // I(w) ~ I_mean + sum_k c_k F_k with c = C^T w.
  const Eigen::VectorXd c = coefficients_.transpose() * w;
  Terms terms;
  for (int k = 0; k < rank_; ++k) {
    terms.index.push_back(k);
    terms.weight.push_back(static_cast<float>(c[k]));
  }
  compose_tiles(terms, static_cast<std::size_t>(rank_), 1.0f, factors_.data(), nullptr, rgb);
}

Image ImageBasis::compose_low_rank(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  Image im(width_, height_);
  compose_low_rank(w, im.rgb.data());
  return im;
}

// --- low rank -----------------------------------------------------------------------------------

LowRankReport ImageBasis::compress(double tolerance, int max_rank) {
  if (!(tolerance >= 0)) throw Error("image basis: low-rank tolerance must be >= 0");
  const int n = n_;
  const std::size_t blocks = tile_count(packed_);
  auto centred_block = [&](std::size_t b, Eigen::MatrixXd& block) {
    const std::size_t begin = b * kChunk, len = std::min(kChunk, packed_ - begin);
    block.resize(n, static_cast<Eigen::Index>(len));
    for (int i = 0; i < n; ++i)
      for (std::size_t j = 0; j < len; ++j) {
        const std::size_t k = tiled(static_cast<std::size_t>(i), begin + j, static_cast<std::size_t>(n));
        const double v = precision_ == BasisPrecision::f32 ? values_f32_[k] : half_to_float(values_f16_[k]);
        block(i, static_cast<Eigen::Index>(j)) = v - packed_mean_[begin + j];
      }
  };
  // Gram matrix of the centred images (double), accumulated per block in parallel.
  std::mutex mutex;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  double image_norm2 = 0;
  parallel_for(0, blocks, [&](std::size_t b0, std::size_t b1) {
    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(n, n), block;
    double local_norm = 0;
    for (std::size_t b = b0; b < b1; ++b) {
      centred_block(b, block);
      local.selfadjointView<Eigen::Lower>().rankUpdate(block);
      const std::size_t begin = b * kChunk;
      for (Eigen::Index j = 0; j < block.cols(); ++j) {
        const double m = packed_mean_[begin + static_cast<std::size_t>(j)];
        local_norm += (block.col(j).array() + m).square().sum();
      }
    }
    std::lock_guard lock(mutex);
    gram += local.selfadjointView<Eigen::Lower>();
    image_norm2 += local_norm;
  });
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  const Eigen::VectorXd lambda = eig.eigenvalues().reverse().cwiseMax(0.0);
  const Eigen::MatrixXd vectors = eig.eigenvectors().rowwise().reverse();
  const double total = lambda.sum();
  const int limit = max_rank > 0 ? std::min(max_rank, n) : n;
  int rank = limit;
  for (int r = 1; r <= limit; ++r) {
    const double rest = lambda.tail(n - r).sum();
    if (total <= 0 || std::sqrt(rest / total) <= tolerance) {
      rank = r;
      break;
    }
  }
  coefficients_ = vectors.leftCols(rank);
  factors_.assign(static_cast<std::size_t>(rank) * blocks * kChunk, 0.0f);
  std::vector<double> max_err(blocks, 0.0);
  parallel_for(0, blocks, [&](std::size_t b0, std::size_t b1) {
    Eigen::MatrixXd block;
    for (std::size_t b = b0; b < b1; ++b) {
      centred_block(b, block);
      const Eigen::MatrixXd f = coefficients_.transpose() * block;  // rank x len
      const std::size_t begin = b * kChunk;
      for (int k = 0; k < rank; ++k)
        for (Eigen::Index j = 0; j < f.cols(); ++j)
          factors_[tiled(static_cast<std::size_t>(k), begin + static_cast<std::size_t>(j),
                         static_cast<std::size_t>(rank))] = static_cast<float>(f(k, j));
      max_err[b] = (block - coefficients_ * f).cwiseAbs().maxCoeff();
    }
  });
  rank_ = rank;
  low_rank_report_.rank = rank;
  const double rest = lambda.tail(n - rank).sum();
  low_rank_report_.relative_error = total > 0 ? std::sqrt(rest / total) : 0.0;
  low_rank_report_.image_relative_error = image_norm2 > 0 ? std::sqrt(rest / image_norm2) : 0.0;
  low_rank_report_.max_abs_error = blocks ? *std::max_element(max_err.begin(), max_err.end()) : 0.0;
  return low_rank_report_;
}

// --- files --------------------------------------------------------------------------------------

void ImageBasis::save(const std::filesystem::path& path, BasisPrecision precision) const {
  const std::int64_t h = height_, w = width_;
  const std::size_t pixels3 = mean_.size();
  SafetensorsWriter writer;
  std::map<std::string, std::string> meta = metadata_;
  meta["format"] = kFormat;
  meta["version"] = "1";
  meta["width"] = std::to_string(width_);
  meta["height"] = std::to_string(height_);
  meta["count"] = std::to_string(n_);
  meta["names"] = nlohmann::json(names_).dump();
  meta["precision"] = precision == BasisPrecision::f16 ? "f16" : "f32";
  if (rank_ > 0) {
    meta["lowrank_rank"] = std::to_string(rank_);
    meta["lowrank_relative_error"] = std::to_string(low_rank_report_.relative_error);
    meta["lowrank_max_abs_error"] = std::to_string(low_rank_report_.max_abs_error);
  }
  for (const auto& [k, v] : meta) writer.add_metadata(k, v);
  if (rank_ > 0) writer.declare("lowrank_coefficients", DType::F64, {n_, rank_});
  writer.declare("mean", DType::F32, {h, w, 3});
  if (!offset_.empty()) writer.declare("offset", DType::F32, {h, w, 3});
  if (rank_ > 0) writer.declare("lowrank_factors", DType::F32, {rank_, h, w, 3});
  writer.declare("images", precision == BasisPrecision::f16 ? DType::F16 : DType::F32, {n_, h, w, 3});
  writer.begin(path);
  if (rank_ > 0) {
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c = coefficients_;
    writer.write(c.data(), static_cast<std::size_t>(c.size()) * sizeof(double));
  }
  writer.write(mean_.data(), pixels3 * sizeof(float));
  if (!offset_.empty()) writer.write(offset_.data(), pixels3 * sizeof(float));
  std::vector<float> buffer(pixels3);
  for (int k = 0; k < rank_; ++k) {
    std::fill(buffer.begin(), buffer.end(), 0.0f);
    for (std::size_t a = 0; a < active_.size(); ++a)
      for (std::size_t c = 0; c < 3; ++c)
        buffer[3 * active_[a] + c] =
            factors_[tiled(static_cast<std::size_t>(k), 3 * a + c, static_cast<std::size_t>(rank_))];
    writer.write(buffer.data(), pixels3 * sizeof(float));
  }
  std::vector<std::uint16_t> halves(precision == BasisPrecision::f16 ? pixels3 : 0);
  for (int i = 0; i < n_; ++i) {
    unpack_into(i, buffer.data());
    if (precision == BasisPrecision::f16) {
      for (std::size_t k = 0; k < pixels3; ++k) halves[k] = float_to_half(buffer[k]);
      writer.write(halves.data(), pixels3 * sizeof(std::uint16_t));
    } else {
      writer.write(buffer.data(), pixels3 * sizeof(float));
    }
  }
  writer.commit();
}

ImageBasis ImageBasis::open(const std::filesystem::path& path) {
  const SafetensorsFile file = SafetensorsFile::open(path);
  const auto& meta = file.metadata();
  auto field = [&](const std::string& key) -> const std::string& {
    const auto it = meta.find(key);
    if (it == meta.end()) throw file_error(path, "not an image basis (metadata '" + key + "' missing)");
    return it->second;
  };
  if (field("format") != kFormat) throw file_error(path, "not an image basis (format is '" + field("format") + "')");
  ImageBasis basis;
  try {
    basis.width_ = std::stoi(field("width"));
    basis.height_ = std::stoi(field("height"));
    basis.n_ = std::stoi(field("count"));
    basis.names_ = nlohmann::json::parse(field("names")).get<std::vector<std::string>>();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw file_error(path, std::string("image basis metadata is malformed: ") + e.what());
  }
  if (basis.width_ <= 0 || basis.height_ <= 0 || basis.n_ <= 0)
    throw file_error(path, "image basis has a non-positive size or count");
  if (!basis.names_.empty() && static_cast<int>(basis.names_.size()) != basis.n_)
    throw file_error(path, "image basis has " + std::to_string(basis.names_.size()) + " names for " +
                               std::to_string(basis.n_) + " images");
  basis.metadata_ = meta;
  const std::int64_t h = basis.height_, w = basis.width_, n = basis.n_;
  const auto mean = file.view<float>("mean", DType::F32, {h, w, 3});
  basis.mean_.assign(mean.begin(), mean.end());
  const std::size_t pixels3 = basis.mean_.size();
  const TensorInfo* images = file.find("images");
  if (!images) throw file_error(path, "image basis has no 'images' tensor");
  std::vector<std::vector<float>> decoded;
  std::vector<const float*> pointers;
  if (images->dtype == DType::F32) {
    const auto v = file.view<float>("images", DType::F32, {n, h, w, 3});
    for (std::int64_t i = 0; i < n; ++i) pointers.push_back(v.data() + static_cast<std::size_t>(i) * pixels3);
    basis.pack(basis.mean_.data(), pointers);
  } else {
    const auto v = file.view<std::uint16_t>("images", DType::F16, {n, h, w, 3});
    const float* table = half_table();
    decoded.resize(static_cast<std::size_t>(n));
    for (std::int64_t i = 0; i < n; ++i) {
      auto& d = decoded[static_cast<std::size_t>(i)];
      d.resize(pixels3);
      const std::uint16_t* src = v.data() + static_cast<std::size_t>(i) * pixels3;
      for (std::size_t k = 0; k < pixels3; ++k) d[k] = table[src[k]];
      pointers.push_back(d.data());
    }
    basis.pack(basis.mean_.data(), pointers);
    decoded.clear();
    basis.convert_to_half();  // exact: the values came from halves
  }
  for (float x : basis.mean_)
    if (!std::isfinite(x)) throw file_error(path, "image basis has NaN or infinite pixels");
  if (file.find("offset")) {
    const auto offset = file.view<float>("offset", DType::F32, {h, w, 3});
    for (float x : offset)
      if (!std::isfinite(x)) throw file_error(path, "image basis has NaN or infinite pixels");
    basis.offset_.assign(offset.begin(), offset.end());
    basis.pack_offset();
  }
  if (const TensorInfo* f = file.find("lowrank_factors")) {
    if (f->shape.empty()) throw file_error(path, "bad low-rank factors");
    const std::int64_t r = f->shape[0];
    const auto factors = file.view<float>("lowrank_factors", DType::F32, {r, h, w, 3});
    const auto coeffs = file.view<double>("lowrank_coefficients", DType::F64, {n, r});
    basis.rank_ = static_cast<int>(r);
    basis.coefficients_ = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        coeffs.data(), n, r);
    basis.factors_.assign(static_cast<std::size_t>(r) * tile_count(basis.packed_) * kChunk, 0.0f);
    for (std::int64_t k = 0; k < r; ++k)
      for (std::size_t a = 0; a < basis.active_.size(); ++a)
        for (std::size_t c = 0; c < 3; ++c)
          basis.factors_[tiled(static_cast<std::size_t>(k), 3 * a + c, static_cast<std::size_t>(r))] =
              factors[static_cast<std::size_t>(k) * pixels3 + 3 * basis.active_[a] + c];
    basis.low_rank_report_.rank = basis.rank_;
    if (auto it = meta.find("lowrank_relative_error"); it != meta.end())
      basis.low_rank_report_.relative_error = std::atof(it->second.c_str());
    if (auto it = meta.find("lowrank_max_abs_error"); it != meta.end())
      basis.low_rank_report_.max_abs_error = std::atof(it->second.c_str());
  }
  return basis;
}

}  // namespace matlas::render
