#pragma once
// Latent maps: pictures of a 2D plane through the latent space, like the albedo map of Soler et
// al. 2018. A LatentPlane maps plane coordinates (u, v) to latent points; latent_grid() computes
// the points of a grid and their GP weights in one batch (server-friendly); render_latent_map()
// colours the grid by albedo, predictive variance or rendered thumbnails (from an ImageBasis) and
// marks and labels each database material.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/progress.h"
#include "formats/image_io.h"

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
  /// bounding box in those dims plus `margin` (fraction of the larger side) on every side.
  static LatentPlane from_dims(const Model& model, int d0, int d1, const Eigen::VectorXd& at, double margin = 0.1);
  /// The plane of the two leading principal axes of the latent points through `at`.
  static LatentPlane pca(const Model& model, const Eigen::VectorXd& at, double margin = 0.1);
  /// dims (0, 1) for q >= 2; for q == 1 the line along dim 0 (v spans nothing).
  static LatentPlane automatic(const Model& model, double margin = 0.1);
};

/// A cols x rows grid of cell centres over the plane (row 0 at v_max, the top of a picture).
struct LatentGrid {
  int cols = 0, rows = 0;
  Eigen::MatrixXd points;   ///< (cols * rows) x q, row-major cells
  Eigen::MatrixXd weights;  ///< n x (cols * rows): GP weights of each point (weights_batch)
};
LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows);

enum class MapLayer { albedo, variance, image };

struct MapOptions {
  MapLayer layer = MapLayer::albedo;
  int size = 768;        ///< picture width and height in pixels
  int cells = 160;       ///< grid cells per side (albedo, variance)
  int thumbnails = 10;   ///< thumbnails per side (image layer)
  bool labels = true;    ///< draw material names (needs the DejaVu font)
  const ImageBasis* basis = nullptr;  ///< required for the image layer
  double albedo_gain = 1.0;           ///< albedo layer: scale before display
};

/// The map as a linear RGB image meant for clamp tone mapping (values in [0, 1]).
Image render_latent_map(const Model& model, const LatentPlane& plane, const MapOptions& options,
                        ProgressSink& progress = null_progress());

/// A perceptual colour map (viridis-like) for t in [0, 1], linear RGB.
Eigen::Array3d colour_map(double t);

}  // namespace matlas::render
