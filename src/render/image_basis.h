#pragma once
// ImageBasis: an image affine in a map point's weights, the one type behind instant previews of
// any map point and the two parts of a GI basis (atlas/gi_basis.h).
//
// The renderer is linear in the BRDF and uses the same samples for every material, and the
// manifold's BRDF is m(w) = mean + sum_i w_i (z_i - mean). So with I_mean the image of the mean
// table (w = 0) and I_i the image of material i (w = e_i), the image of any weights w is
//
//     I(w) = I_mean + sum_i w_i (I_i - I_mean)
//
// exactly (to float rounding) what a direct render of m(w) with the same seed gives.
//
// Storage (safetensors, float32 or float16 images):
//   "mean"    F32 [H, W, 3]      image of the mean table
//   "images"  F32|F16 [n, H, W, 3] image of each database material
//   optional "offset" F32 [H, W, 3] (added to every composition; set_offset)
//   optional "lowrank_factors" F32 [r, H, W, 3] and "lowrank_coefficients" F64 [n, r]
//   metadata: format=matlas-image-basis, version, width, height, count, names (JSON), precision,
//             and what the caller adds (scene, env, camera, spp, seed, model name and fingerprint).
//
// In memory only the pixels where some material differs from the mean ("active" pixels: where
// the object is seen) are kept, packed, in the file's precision; composing reads n * active
// values, which bounds its time by memory bandwidth. compress() adds an optional low-rank form
// (eigen-decomposition of the n x n Gram matrix of the centred images): I(w) ~ I_mean +
// sum_k c_k(w) F_k with rank r <= n, its error measured.
//
// A basis of a model (its mean and database materials, rendered with identical samples) is made
// by atlas/model_basis.h, a GI basis's parts by atlas/gi_basis.h; this class only stores and
// composes images.
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "formats/image_io.h"

namespace matlas::render {

enum class BasisPrecision { f32, f16 };

/// Result of ImageBasis::compress.
struct LowRankReport {
  int rank = 0;
  /// ||D - D_r||_F / ||D||_F over the centred images D (predicted from the eigenvalues).
  double relative_error = 0;
  /// The same error relative to the norm of the material images themselves.
  double image_relative_error = 0;
  /// Largest absolute pixel error over all material images (measured).
  double max_abs_error = 0;
};

class ImageBasis {
public:
  ImageBasis() = default;
  /// From rendered images (all width x height); names.size() == images.size() (or empty).
  ImageBasis(Image mean, std::span<const Image> images, std::vector<std::string> names = {},
             std::map<std::string, std::string> metadata = {});

  /// Opens a basis file; throws matlas::Error naming the file if it is not a valid basis.
  static ImageBasis open(const std::filesystem::path& path);
  /// Writes the basis atomically, images in `precision` (and the low-rank form if computed).
  void save(const std::filesystem::path& path, BasisPrecision precision = BasisPrecision::f32) const;

  int width() const { return width_; }
  int height() const { return height_; }
  int count() const { return n_; }  ///< number of material images n
  const std::vector<std::string>& names() const { return names_; }
  std::map<std::string, std::string>& metadata() { return metadata_; }
  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  BasisPrecision precision() const { return precision_; }
  /// Fraction of pixels where some material differs from the mean.
  double active_fraction() const;
  /// Bytes read by one compose() of weights that are all non-zero (the packed image values).
  std::size_t compose_bytes() const;

  /// Linear RGB of the image for weights w (length n): width * height * 3 floats written to rgb.
  /// Reads only the images of non-zero weights (convex weights have a handful). Multi-threaded;
  /// float16 storage uses F16C when the CPU has it. Thread-safe.
  void compose(const Eigen::Ref<const Eigen::VectorXd>& w, float* rgb) const;
  Image compose(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// The same through the low-rank form (compress() first); falls back to compose() without it.
  void compose_low_rank(const Eigen::Ref<const Eigen::VectorXd>& w, float* rgb) const;
  Image compose_low_rank(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// compose() or compose_low_rank(), whichever reads fewer images: exact when the weights have
  /// no more non-zero entries than the rank (convex weights: a handful), else the low-rank form.
  void compose_fast(const Eigen::Ref<const Eigen::VectorXd>& w, float* rgb) const;
  Image compose_fast(const Eigen::Ref<const Eigen::VectorXd>& w) const;

  Image mean_image() const;
  Image material_image(int i) const;

  /// A constant image added to every composition, I(w) = offset + (1 - sum w) I_mean + sum_i
  /// w_i I_i (a GI basis's paths that never touch the object); saved with the basis. None: zero.
  void set_offset(const Image& offset);
  Image offset_image() const;  ///< zeros when none was set

  /// Stores the images in float16 (what save(f16) writes) and returns the relative L2 error of
  /// the material images against the previous values.
  double convert_to_half();

  /// Computes the low-rank form with the smallest rank whose relative error (Frobenius, centred
  /// images) is <= tolerance, at most max_rank (<= 0: n). tolerance 0 keeps every component.
  LowRankReport compress(double tolerance, int max_rank = 0);
  int low_rank() const { return rank_; }
  const LowRankReport& low_rank_report() const { return low_rank_report_; }

private:
  void pack(const float* mean, const std::vector<const float*>& images);
  void unpack_into(int i, float* rgb) const;
  void pack_offset();
  /// The rows a composition reads and their weights.
  struct Terms {
    std::vector<int> index;
    std::vector<float> weight;
  };
  /// rgb = mean_weight * mean + sum_t weight_t * row_{index_t} over `rows` tiled rows (f32 or
  /// f16, the other null).
  void compose_tiles(const Terms& terms, std::size_t rows, float mean_weight, const float* f32,
                     const std::uint16_t* f16, float* rgb) const;

  int width_ = 0, height_ = 0, n_ = 0;
  std::vector<std::string> names_;
  std::map<std::string, std::string> metadata_;
  BasisPrecision precision_ = BasisPrecision::f32;
  std::vector<float> mean_;               // width * height * 3
  std::vector<std::uint32_t> active_;     // active pixel indices (ascending)
  std::size_t packed_ = 0;                // 3 * active_.size()
  std::vector<float> packed_mean_;        // mean at the active pixels
  std::vector<float> offset_;             // width * height * 3, or empty: no offset
  std::vector<float> packed_offset_;      // offset at the active pixels (empty without one)
  std::vector<float> values_f32_;         // n rows of packed_ values, tiled (image_basis.cpp)
  std::vector<std::uint16_t> values_f16_; // the same in float16 when precision_ == f16
  int rank_ = 0;
  std::vector<float> factors_;            // rank rows of packed_ values, tiled
  Eigen::MatrixXd coefficients_;          // n x rank
  LowRankReport low_rank_report_;
};

}  // namespace matlas::render
