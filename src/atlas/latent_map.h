#pragma once
// Latent maps: pictures of a 2D plane through the latent space, like the albedo map of Soler et
// al. 2018. The plane and its grid are latent_plane.h's, the layers map_layers.h's (the same as
// the server's); render_latent_map() colours the grid by a layer or by rendered thumbnails (from
// an ImageBasis), marks each database material and labels as many as fit without overlapping
// (render/label_layout.h).
//
// Honesty rules: the picture frames the data (the latent points' bounding box plus a margin, with
// the picture's aspect following the box), and where the predictive variance says a point is far
// from the data the albedo and image layers fade into a hatched neutral grey instead of showing
// the database mean as if it were a material; a legend under the map says so.
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "atlas/latent_plane.h"
#include "atlas/map_layers.h"
#include "core/progress.h"
#include "formats/image_io.h"
#include "render/image_basis.h"
#include "render/label_layout.h"

namespace matlas::atlas {

struct MapOptions {
  MapLayer layer = MapLayer::albedo;
  int size = 768;        ///< the map's longer side in pixels (the other follows the plane's aspect)
  int cells = 160;       ///< grid cells along the longer side (albedo, variance, plausibility)
  int thumbnails = 10;   ///< thumbnails along the longer side (image layer)
  bool labels = true;    ///< draw material names (needs the DejaVu font), decluttered
  bool legend = true;    ///< a legend strip under the map (needs the font for its text)
  const render::ImageBasis* basis = nullptr;  ///< required for the image layer
  /// Albedo gain, and the predictive variances where the albedo and image layers start fading
  /// into the hatched grey of "no data here" and where the fade is complete.
  LayerStyle style;
};

/// Width and height in pixels of the map part of a picture of `plane` whose longer side is `size`.
std::pair<int, int> map_size(const LatentPlane& plane, int size);

/// Decluttered labels of the database materials on a map of `width` x `height` pixels whose
/// labels are `text_size` pixels tall (label_layout.h); entry i is material i.
struct MapLabels {
  std::vector<Eigen::Vector2d> markers;  ///< pixel position of each material
  std::vector<render::LabelPlacement> labels;
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

}  // namespace matlas::atlas
