#pragma once
// The one grid of latent maps (the `matlas map` pictures and the server's map layers): a 2D plane
// through the latent space, framed on the data or on a given rectangle, and a grid of cell
// centres over it with each point's weights and predictive variance.
#include <limits>

#include <Eigen/Core>

#include "manifold/model.h"

namespace matlas::atlas {

/// x(u, v) = origin + u * axis_u + v * axis_v, over [u_min, u_max] x [v_min, v_max].
struct LatentPlane {
  Eigen::VectorXd origin, axis_u, axis_v;
  double u_min = -1, u_max = 1, v_min = -1, v_max = 1;

  Eigen::VectorXd point(double u, double v) const { return origin + u * axis_u + v * axis_v; }
  /// Plane coordinates of the orthogonal projection of x (axes are orthonormal).
  Eigen::Vector2d project(const Eigen::VectorXd& x) const {
    return {(x - origin).dot(axis_u), (x - origin).dot(axis_v)};
  }
  /// The u of the centres of `cols` columns of cells across [u_min, u_max], left to right; the v
  /// of `rows` rows' centres, top (v_max) to bottom: cell (r, c) of a grid is point(u[c], v[r]).
  Eigen::VectorXd cell_u(int cols) const {
    Eigen::VectorXd u(cols);
    for (int c = 0; c < cols; ++c) u[c] = u_min + (c + 0.5) / cols * (u_max - u_min);
    return u;
  }
  Eigen::VectorXd cell_v(int rows) const {
    Eigen::VectorXd v(rows);
    for (int r = 0; r < rows; ++r) v[r] = v_max - (r + 0.5) / rows * (v_max - v_min);
    return v;
  }

  /// The rectangle [u0, u1] x [v0, v1] of latent axes d0 (u) and d1 (v) through `at` (which gives
  /// the other coordinates): what the server's map layers show. Throws on bad axes or sizes.
  static LatentPlane rectangle(const Eigen::VectorXd& at, int d0, int d1, double u0, double u1, double v0,
                               double v1);
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

/// A cols x rows grid of cell centres over the plane (row 0 at v_max, the top of a picture), with
/// the weights and predictive variance of every point as the model's interpolation mode gives
/// them (Model::predict_batch: one batched GP product, then in the convex mode the projections,
/// each started from the neighbouring cell's: the cells go to it in serpentine order), so that
/// maps show what a preview or an export at that point would give.
struct LatentGrid {
  int cols = 0, rows = 0;
  Eigen::MatrixXd points;    ///< (cols * rows) x q, row-major cells
  Eigen::MatrixXd weights;   ///< n x (cols * rows)
  Eigen::VectorXd variance;  ///< cols * rows
};
LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows);
/// The same with the weights of `mode` (the variance is the same in every mode). In the convex
/// mode only the cells whose predictive variance is below `project_below` are projected; the
/// others keep the GP's weights (for layers that fade such cells out completely).
LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows, Interpolation mode,
                       double project_below = std::numeric_limits<double>::infinity());

}  // namespace matlas::atlas
