#pragma once
// The plausibility gallery (Soler et al. 2018): the same object rendered with materials picked
// on the manifold and real database materials, shuffled into a numbered grid, with the answer key.
//
// Picks cover the map's variety instead of its densest part: every material is described by an
// appearance feature vector (AppearanceFeatures: brightness, two chromaticities and gloss, each
// in units of its spread over the database), the real materials are chosen by farthest-point
// sampling over the database's features, and the generated ones by farthest-point sampling over
// candidate points between latent neighbours (continuing from the real picks), keeping only
// candidates that are near the data (low predictive variance), physically plausible, and not a
// copy of a database material. See docs/RENDERING.md.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "formats/image_io.h"
#include "manifold/model.h"
#include "render/refinement.h"

namespace matlas::render {
class ImageBasis;
class Scene;
struct RenderSettings;
}  // namespace matlas::atlas

namespace matlas::atlas {

/// Appearance features of tables m(w): rows of [ln L, ln(r/g), ln(b/g), gloss] divided by the
/// spread (standard deviation, with a floor) of each feature over the database's materials, where
/// (r, g, b) is the albedo at normal incidence, L its luminance and gloss = ln(pi f_peak / L), the
/// peak value f_peak (luminance at the two smallest theta_h bins, theta_d about 10 degrees,
/// phi_d = 90 degrees) relative to a Lambertian of the same albedo (0 for a diffuse material,
/// about 5-9 for metals and glossy coatings). Euclidean distances between rows compare materials.
class AppearanceFeatures {
public:
  static constexpr int kCount = 4;
  explicit AppearanceFeatures(const Model& model);
  /// m x kCount scaled features of the columns of W (n x m).
  Eigen::MatrixXd operator()(const Eigen::MatrixXd& W) const;
  /// The unscaled [ln L, ln(r/g), ln(b/g), gloss] (m x kCount).
  Eigen::MatrixXd raw(const Eigen::MatrixXd& W) const;
  /// The database materials' scaled features (n x kCount).
  const Eigen::MatrixXd& materials() const { return materials_; }
  const Eigen::Vector4d& scale() const { return scale_; }

private:
  const Model& model_;
  std::vector<std::size_t> peak_bins_;
  Eigen::Vector4d scale_;
  Eigen::MatrixXd materials_;
};

struct GalleryOptions {
  int random = 11;            ///< generated materials
  int real = 4;               ///< database materials
  std::uint64_t seed = 1;     ///< jitter of the candidates, first real pick, shuffle
  double max_variance = 0.2;  ///< generated points must have predictive variance below this
  /// Skip candidates with negative values or an albedo outside [0, the inputs' largest].
  bool plausible_only = true;
  /// Skip candidates closer than this (feature units) to a database material: copies.
  double min_novelty = 0.25;
  int neighbours = 6;  ///< candidates lie between each material and this many latent neighbours
};

struct GalleryEntry {
  bool real = false;
  std::string name;   ///< database name, or "generated"
  Eigen::VectorXd x;  ///< latent point
  double variance = 0;
  Eigen::Vector3d albedo = Eigen::Vector3d::Zero();  ///< at normal incidence
  double gloss = 0;                                  ///< ln(pi f_peak / L) (AppearanceFeatures)
  double novelty = 0;    ///< feature distance to the nearest other database material
  bool plausible = true;
  double negative_fraction = 0, max_albedo = 0;
};

/// What the picking did (for the key and the command's report).
struct GalleryStats {
  int candidates = 0;           ///< generated candidates considered
  int rejected_variance = 0;    ///< variance above the limit
  int rejected_implausible = 0; ///< negative values or albedo out of range (of those left)
  int rejected_copies = 0;      ///< closer than min_novelty to a database material (of those left)
  std::vector<std::string> relaxed;  ///< filters dropped because too few candidates passed
  double min_distance = 0;      ///< smallest feature distance between two picks
};

/// The picks, already shuffled. Deterministic for the seed.
std::vector<GalleryEntry> pick_gallery(const Model& model, const GalleryOptions& options, GalleryStats* stats = nullptr);

/// The grid picture: cells in reading order, numbered from 1 in their corner, each rendered with
/// the basis if given (same scene as the basis) or else directly with `settings` and `scene`: with
/// `target_error` > 0 each cell refined (render/progressive_render.h, adaptive sampling) until its
/// estimated relative RMS error inside the object is at most that, settings->spp samples per
/// pixel at most, so that no cell gives itself away by its noise; `refined` then gets each cell's
/// final state. The result is linear RGB (write with a tone map).
Image render_gallery(const Model& model, const std::vector<GalleryEntry>& entries, const render::Scene* scene,
                     const render::RenderSettings* settings, const render::ImageBasis* basis,
                     ProgressSink& progress = null_progress(), double target_error = 0.0,
                     std::vector<render::RefinementState>* refined = nullptr);

/// The answer key: {"interpolation": "gp"|"convex", "selection": {stats},
///  "cells": [{"cell": 1, "real": true, "name": ..., "x": [...], "variance": ..., "albedo": [r, g, b],
///             "gloss": ..., "novelty": ..., "plausible": ...}, ...]}.
nlohmann::json gallery_key(const Model& model, const std::vector<GalleryEntry>& entries, const GalleryStats& stats);

}  // namespace matlas::atlas
