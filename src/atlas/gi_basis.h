#pragma once
// GI image bases (docs/GI.md): for a model and a scene with a measured object, P (paths that
// never touch the object), and per material k of the n + 1 (k = 0: the model's mean table, k =
// i + 1: input i) the image N z_k of the paths touching it once and the full image part
// N z_k + I2_k, all with the same paths and random numbers. For weights w of a map point x,
// with coefficients a = (1 - sum w, w_1, ..., w_n) (the tables' m(x) = sum_k a_k z_k):
//
//   I1(x) = P + sum_k a_k N z_k                   exact: N is linear in the table
//   I(x) ~= P + sum_k a_k (N z_k + I2_k)          I2 interpolated with the same weights
//
// The second is exact at the inputs (and at w = 0) and approximates I2(x), which is quadratic
// and higher in m(x), elsewhere.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/communicator.h"
#include "core/progress.h"
#include "formats/image_io.h"
#include "manifold/model.h"
#include "pathtrace/tracer.h"
#include "render/image_basis.h"

namespace matlas::atlas {

/// A GI basis is one render::ImageBasis per part (its "mean" image X_0, its material images
/// X_1..X_n, P its offset): composing one is an image basis's composition.
class GiBasis {
public:
  enum class Part { all, i1 };

  GiBasis() = default;
  /// p, and per material k (n + 1) the once-touched image and the full part (once + more).
  GiBasis(Image p, const std::vector<Image>& linear, const std::vector<Image>& full,
          std::vector<std::string> names, std::map<std::string, std::string> metadata);

  int width() const { return p_.width; }
  int height() const { return p_.height; }
  int count() const { return static_cast<int>(names_.size()); }  ///< n
  const std::vector<std::string>& names() const { return names_; }
  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  const Image& p() const { return p_; }
  /// A part's images as an image basis (its mean image: k = 0, the mean table's).
  const render::ImageBasis& part(Part part) const { return part == Part::i1 ? linear_ : full_; }
  /// Image k (0: mean table) of a part: N z_k (i1) or N z_k + I2_k (all).
  Image image(Part part, int k) const;

  /// The image of weights w (length n): P + sum_k a_k X_k, X the part's images
  /// (render::ImageBasis::compose, multi-threaded).
  Image compose(const Eigen::Ref<const Eigen::VectorXd>& w, Part part = Part::all) const;
  /// The same into `rgb` (width * height * 3 floats), without allocating.
  void compose(const Eigen::Ref<const Eigen::VectorXd>& w, Part part, float* rgb) const;

  /// Stores both parts' images in float16 (half the bytes per composition; relative rounding
  /// 2^-11); image() and save() return the rounded values from then on. Returns the relative L2
  /// error of the rounded images (render::ImageBasis::convert_to_half), the larger of the parts'.
  double convert_to_half();
  bool is_half() const { return linear_.precision() == render::BasisPrecision::f16; }

  /// safetensors (float32 whatever the memory form): p F32 [H,W,3], linear and full F32 [n+1,H,W,3]; metadata plus "names" (JSON).
  void save(const std::filesystem::path& path) const;
  /// matlas::Error naming the file when it is not a GI basis or is inconsistent.
  static GiBasis load(const std::filesystem::path& path);

private:
  Image p_;
  render::ImageBasis linear_, full_;
  std::vector<std::string> names_;
  std::map<std::string, std::string> metadata_;
};

struct GiBasisOptions {
  int batch = 16;                   ///< materials traced per pass
  std::filesystem::path cache;      ///< folder of per-material images (resumable); empty: none
};

/// What identifies a basis: model fingerprint, scene and trace settings (a cache entry is reused
/// only when its key matches).
std::string gi_basis_key(const Model& model, const pathtrace::World& world, const pathtrace::TraceSettings& settings);

/// Traces the basis in passes of `batch` materials, each material's images cached in
/// options.cache (reused when present with the same key: an interrupted build resumes).
/// Split across processes (`mpirun -np P matlas basis --scene floor`): every rank traces a
/// contiguous share of the n + 1 materials (the same paths: its images are the single process's)
/// and caches them, rank 0 also P, and rank 0 gathers the basis; the other ranks return an empty one.
GiBasis build_gi_basis(const Model& model, const pathtrace::World& world, const pathtrace::TraceSettings& settings,
                       const GiBasisOptions& options, ProgressSink& progress = null_progress(),
                       Communicator& comm = serial_communicator());

/// The basis at `path` when it exists with the key of these settings (gi_basis_key), else traced
/// by build_gi_basis with its cache in PATH.cache/ (resumable) and saved at `path`. A file at
/// `path` of other settings or another model is traced again and replaced.
GiBasis open_or_build_gi_basis(const Model& model, const pathtrace::World& world, const pathtrace::TraceSettings& settings,
                               const std::filesystem::path& path, int batch, ProgressSink& progress = null_progress());

/// matlas::Error naming `path` unless the basis was traced for `model` (its fingerprint).
void require_basis_of_model(const GiBasis& basis, const Model& model, const std::filesystem::path& path);

/// The name of the scene a basis was traced in (its "scene" metadata), empty if it has none.
std::string gi_basis_scene_name(const GiBasis& basis);

}  // namespace matlas::atlas
