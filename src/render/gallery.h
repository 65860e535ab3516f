#pragma once
// The plausibility gallery (Soler et al. 2018): the same object rendered with materials picked
// on the manifold (random points inside the data region, with low predictive variance) and real
// database materials, shuffled into a numbered grid, with the answer key.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "formats/image_io.h"

namespace matlas {
class Model;
}

namespace matlas::render {

class ImageBasis;
class Scene;
struct RenderSettings;

struct GalleryOptions {
  int random = 11;            ///< generated materials
  int real = 4;               ///< database materials
  std::uint64_t seed = 1;     ///< picks and shuffle
  double max_variance = 0.2;  ///< generated points must have predictive variance below this
};

struct GalleryEntry {
  bool real = false;
  std::string name;   ///< database name, or "generated"
  Eigen::VectorXd x;  ///< latent point
  double variance = 0;
};

/// The picks, already shuffled. Generated points are convex combinations of a material and one
/// of its 3 nearest neighbours (t in [0.2, 0.8]), redrawn until their variance is below the limit
/// (the lowest of 64 draws otherwise). Deterministic for the seed.
std::vector<GalleryEntry> pick_gallery(const Model& model, const GalleryOptions& options);

/// The grid picture: cells in reading order, numbered from 1 in their corner, each rendered with
/// the basis if given (same scene as the basis) or else directly with `settings` and `scene`.
/// The result is linear RGB (write with a tone map).
Image render_gallery(const Model& model, const std::vector<GalleryEntry>& entries, const Scene* scene,
                     const RenderSettings* settings, const ImageBasis* basis, ProgressSink& progress = null_progress());

/// The answer key: [{"cell": 1, "real": true, "name": ..., "x": [...], "variance": ...}, ...].
nlohmann::json gallery_key(const std::vector<GalleryEntry>& entries);

}  // namespace matlas::render
