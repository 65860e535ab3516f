#pragma once
// Model: a built material manifold, opened read-only by memory-mapping a `.matlas` file
// (docs/MODEL_FORMAT.md). It answers every query of the GP interpolation
//
//     m(x) = mean + sum_i w_i(x) (z_i - mean),   w(x) = K^-1 k(x),
//
// where z_i are the n input tables restricted to the kept columns (columns where every input has a
// measurement; the others read as missing). The inputs are stored column-interleaved (one
// contiguous run of n values per column), so a single value at x costs one dot product of length n
// once w(x) is known: m(x) = (1 - sum w) mean + sum_i w_i z_i, which returns z_i exactly at x_i.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>  // metadata(): include manifold/model_metadata.h to read it

#include "brdf/brdf_table.h"
#include "gp/convex_weights.h"
#include "gp/posterior.h"
#include "manifold/interpolation.h"
#include "manifold/model_format.h"  // kAlbedoAngles

namespace matlas {

class Model {
public:
  /// Opens and validates a model; throws matlas::Error naming the file if it is missing,
  /// truncated, corrupted or not a matlas model.
  static Model open(const std::filesystem::path& path);

  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;
  ~Model();

  // --- Description ---
  const std::filesystem::path& path() const;
  int count() const;  ///< n, the number of input materials
  int dim() const;    ///< q, the latent dimension
  const std::vector<std::string>& names() const;
  /// Index of a material by name; throws matlas::Error listing close names if unknown.
  int index_of(const std::string& name) const;
  const Eigen::MatrixXd& latent() const;  ///< n x q latent points
  const MerlDims& dims() const;
  std::size_t kept_columns() const;  ///< D'
  const gp::GpPosterior& posterior() const;
  /// Everything in the header's metadata (names, kernel, optimiser, likelihood, sources, ...);
  /// manifold/model_metadata.h declares the JSON type (and helpers), so that includers of this
  /// header do not all compile nlohmann/json.hpp.
  const nlohmann::json& metadata() const;
  /// Centred Gram matrix S = (Z - mean)(Z - mean)^T of the inputs over the kept columns (n x n).
  const Eigen::MatrixXd& gram() const;
  /// Per-material directional albedo curves, n x (kAlbedoAngles * 3), [theta][channel].
  const Eigen::MatrixXd& material_albedo() const;
  /// Latent bounding box, min and max per dimension.
  Eigen::VectorXd latent_min() const;
  Eigen::VectorXd latent_max() const;

  // --- Interpolation mode ---
  /// The mode of the queries that name none: the mode the model was built with (metadata
  /// "interpolation"; "gp" for models without it), or the one given to with_interpolation.
  Interpolation interpolation() const;
  /// Another handle on the same opened model (nothing is copied or read again) whose queries
  /// default to `mode` (e.g. `matlas serve --interpolation gp`). The opened model itself is never
  /// changed: handles with different modes can be used from different threads at once.
  Model with_interpolation(Interpolation mode) const;
  /// The convex mode's metric A (gp/convex_weights.h: the layout Gram over its mean diagonal plus
  /// the ridge), in either mode.
  const Eigen::MatrixXd& convex_metric() const;

  // --- Queries ---
  // Each query that depends on the mode takes it as an argument; without it, interpolation().
  /// The interpolation weights of x in `mode` (length n), for the tables
  /// m(x) = (1 - sum w) mean + sum_i w_i z_i (core/combination.h): the GP's w(x) = K^-1 k(x), or
  /// convex weights (non-negative, sum 1). At a material's own point exactly e_i in both modes.
  Eigen::VectorXd weights(const Eigen::Ref<const Eigen::VectorXd>& x, Interpolation mode) const;
  Eigen::VectorXd weights(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// What a sequence of weights(x, warm) queries shares: the last convex solve's state (empty at
  /// first; one per sequence, not shared between threads).
  using WarmStart = gp::ConvexProjection::WarmStart;
  /// weights(x) with the convex solve started from the previous point's of the sequence: faster
  /// for a nearby point, and the same bits as weights(x) (the solution is settled on its support,
  /// gp/convex_weights.h).
  Eigen::VectorXd weights(const Eigen::Ref<const Eigen::VectorXd>& x, WarmStart& warm) const;
  /// Weights (n x m, column j for row j of points, m x q) and GP predictive variances (length m)
  /// of many points, computed in parallel; the same as weights() and variance() per point.
  struct Prediction {
    Eigen::MatrixXd weights;
    Eigen::VectorXd variance;
  };
  Prediction predict_batch(const Eigen::MatrixXd& points, Interpolation mode) const;
  Prediction predict_batch(const Eigen::MatrixXd& points) const;
  /// The GP's weights and variances of the cells of a regular grid on a plane (column r * u.size()
  /// + c for the cell origin + u[c] axis_u + v[r] axis_v), through the kernel's separability on
  /// the plane (gp::GpPosterior::predict_grid; equal to predict_batch(points, gp) to about 1e-10).
  /// Throws matlas::Error if the plane does not have q coordinates or a value is not finite.
  Prediction predict_grid(const Eigen::VectorXd& origin, const Eigen::VectorXd& axis_u, const Eigen::VectorXd& axis_v,
                          const Eigen::VectorXd& u, const Eigen::VectorXd& v) const;
  /// The weights in `mode` for given GP weights w (centred form): w itself, or its convex
  /// projection.
  Eigen::VectorXd weights_from_gp(const Eigen::Ref<const Eigen::VectorXd>& w, Interpolation mode) const;
  Eigen::VectorXd weights_from_gp(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// weights_from_gp of every column of W (n x m), in place, in parallel (for `mode` convex each
  /// solve starts from the previous column's: pass neighbouring points in order).
  void weights_from_gp_batch(Eigen::Ref<Eigen::MatrixXd> W, Interpolation mode) const;
  /// Weights with all mass on material i.
  Eigen::VectorXd material_weights(int i) const;
  /// GP predictive variance in kernel units: 0 at the data, towards 1 far from it.
  double variance(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// Whether value index v (channel * bins + bin) is a kept column.
  bool kept(std::size_t value_index) const;
  /// Physical value of value index v for weights w; NaN where the column was dropped.
  double value(std::size_t value_index, const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// Physical RGB of one bin for weights w (dropped channels read as 0).
  Rgb bin_rgb(std::size_t bin, const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// f(wi, wo) by MERL's nearest-bin lookup through the model (local frame, normal +z).
  Rgb lookup(const Vec3& wi, const Vec3& wo, const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// The whole table for weights w; dropped columns are missing (written -1 to MERL files).
  BrdfTable table(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// Directional albedo curve for weights w, by linearity from the per-material curves:
  /// kAlbedoAngles entries.
  std::vector<Rgb> albedo_curve(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// The albedo curves of many weight vectors (columns of W, n x m) at once:
  /// (kAlbedoAngles * 3) x m, rows [theta][channel].
  Eigen::MatrixXd albedo_batch(const Eigen::MatrixXd& W) const;

  // --- Raw storage (for fast paths such as rendering and benchmarks) ---
  /// Kept column of value index v, or -1.
  int column_of(std::size_t value_index) const;
  /// Mean over materials of kept column c.
  float mean(std::size_t column) const;
  /// The n input values of kept column c, contiguous (float32 storage), or nullptr when the model
  /// stores float16 (use data()).
  const float* data_f32(std::size_t column) const;
  /// The n input values of kept column c, converted to float whatever the storage.
  void data(std::size_t column, float* out) const;
  /// Storage precision of the stored input data: "F32" or "F16".
  const std::string& storage() const;

  // --- The file behind the model (it is memory-mapped, formats/safetensors.h MappedFile) ---
  /// same: the file at path() is the one opened; modified: it was rewritten or truncated in place
  /// (the mapped data can no longer be trusted); replaced: another file is there now, or none
  /// (renamed over or removed: the mapped data is intact, the path holds something new).
  enum class FileState { same, modified, replaced };
  FileState file_state() const;
  /// Pages read as zeros because the file was truncated while open (0 for an intact file):
  /// answers computed while this count changed are wrong.
  std::uint64_t mapping_faults() const;

private:
  /// Throws matlas::Error unless x has q finite coordinates.
  void check_point(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  struct Impl;
  Model(std::shared_ptr<const Impl> impl, Interpolation mode);
  std::shared_ptr<const Impl> impl_;  ///< the opened file: never changed after open()
  Interpolation interpolation_;        ///< this handle's default mode
};

}  // namespace matlas
