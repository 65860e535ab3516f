#pragma once
// Latent maps: pictures of a 2D plane through the latent space, like the albedo map of Soler et
// al. 2018. A LatentPlane maps plane coordinates (u, v) to latent points; latent_grid() computes
// the points of a grid and their GP weights in one batch (server-friendly); render_latent_map()
// colours the grid by albedo, predictive variance or rendered thumbnails (from an ImageBasis),
// marks each database material and labels as many as fit without overlapping (label_layout.h).
//
// Honesty rules: the picture frames the data (the latent points' bounding box plus a margin, with
// the picture's aspect following the box), and where the predictive variance says a point is far
// from the data the albedo and image layers fade into a hatched neutral grey instead of showing
// the database mean as if it were a material; a legend under the map says so.
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "formats/image_io.h"
#include "render/label_layout.h"

namespace matlas {
class Model;
}

namespace matlas::render {

class ImageBasis;

/// x(u, v) = origin + u * axis_u + v * axis_v, over [u_min, u_max] x [v_min, v_max].
struct LatentPlane {
  Eigen::VectorXd origin, axis_u, axis_v;
  double u_min = -1, u_max = 1, v_min = -1, v_max = 1;

  Eigen::VectorXd point(double u, double v) const { return origin + u * axis_u + v * axis_v; }
  /// Plane coordinates of the orthogonal projection of x (axes are orthonormal).
  Eigen::Vector2d project(const Eigen::VectorXd& x) const {
    return {(x - origin).dot(axis_u), (x - origin).dot(axis_v)};
  }

  /// Axis-aligned plane through `at` spanned by latent dims d0 and d1; the extent is the data's
  /// bounding box in those dims plus `margin` (fraction of the larger side) on every side. The
  /// extent is not squared: the shorter side is only widened (about its centre) to keep the
  /// aspect within 1:3.
  static LatentPlane from_dims(const Model& model, int d0, int d1, const Eigen::VectorXd& at, double margin = 0.1);
  /// The plane of the two leading principal axes of the latent points through `at`.
  static LatentPlane pca(const Model& model, const Eigen::VectorXd& at, double margin = 0.1);
  /// dims (0, 1) for q >= 2; for q == 1 the line along dim 0 (v spans nothing).
  static LatentPlane automatic(const Model& model, double margin = 0.1);
};

/// Reframes `plane` on the core of the data: the box (plus `margin`, as above) of the materials
/// within 4 median distances of the per-axis median of the projected points (at least half of
/// them). For a layout where a few outliers stretch the box and most materials crowd in a corner.
/// Returns how many materials fall outside the new frame.
int frame_core(const Model& model, LatentPlane& plane, double margin = 0.1);

/// A cols x rows grid of cell centres over the plane (row 0 at v_max, the top of a picture).
struct LatentGrid {
  int cols = 0, rows = 0;
  Eigen::MatrixXd points;   ///< (cols * rows) x q, row-major cells
  Eigen::MatrixXd weights;  ///< n x (cols * rows): the model's weights of each point (grid_weights)
};
LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows);

/// The weights (n x m) of m points (rows of `points`) as the model's interpolation mode gives
/// them (Model::predict_batch: one batched GP solve, then the convex projection per point in the
/// convex mode), so that maps show what a preview or an export at that point would give.
Eigen::MatrixXd grid_weights(const Model& model, const Eigen::MatrixXd& points);

enum class MapLayer { albedo, variance, image };

/// Default predictive variances where maps start fading into "no data here" and where the fade is
/// complete (the browser uses the same, from GET /api/model).
inline constexpr double kFadeFrom = 0.5, kFadeTo = 0.9;

struct MapOptions {
  MapLayer layer = MapLayer::albedo;
  int size = 768;        ///< the map's longer side in pixels (the other follows the plane's aspect)
  int cells = 160;       ///< grid cells along the longer side (albedo, variance)
  int thumbnails = 10;   ///< thumbnails along the longer side (image layer)
  bool labels = true;    ///< draw material names (needs the DejaVu font), decluttered
  bool legend = true;    ///< a legend strip under the map (needs the font for its text)
  const ImageBasis* basis = nullptr;  ///< required for the image layer
  double albedo_gain = 1.0;           ///< albedo layer: scale before display
  /// Predictive variance where the albedo and image layers start fading into the hatched grey of
  /// "no data here", and where the fade is complete.
  double fade_from = kFadeFrom, fade_to = kFadeTo;
};

/// Width and height in pixels of the map part of a picture of `plane` whose longer side is `size`.
std::pair<int, int> map_size(const LatentPlane& plane, int size);

/// How much of "no data here" to show at predictive variance v: 0 below `from`, 1 above `to`,
/// smooth in between.
double uncertainty_fade(double variance, double from, double to);

/// The neutral "no data here" colour at pixel (x, y) (linear RGB): mid grey with dark diagonal
/// hatching, so that it cannot be mistaken for a grey material.
Eigen::Array3d unknown_colour(int x, int y);

/// Decluttered labels of the database materials on a map of `width` x `height` pixels whose
/// labels are `text_size` pixels tall (label_layout.h); entry i is material i.
struct MapLabels {
  std::vector<Eigen::Vector2d> markers;  ///< pixel position of each material
  std::vector<LabelPlacement> labels;
  int shown() const;
};
MapLabels map_labels(const Model& model, const LatentPlane& plane, int width, int height, float text_size,
                     double marker_radius);
/// The labels exactly as render_latent_map places them for these options.
MapLabels map_labels(const Model& model, const LatentPlane& plane, const MapOptions& options);

/// The map as a linear RGB image meant for clamp tone mapping (values in [0, 1]): the map
/// (map_size) and, with `legend`, a legend strip under it.
Image render_latent_map(const Model& model, const LatentPlane& plane, const MapOptions& options,
                        ProgressSink& progress = null_progress());

/// A perceptual colour map (viridis-like) for t in [0, 1], linear RGB.
Eigen::Array3d colour_map(double t);

}  // namespace matlas::render
