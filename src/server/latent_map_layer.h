#pragma once
// Background layers of the latent map: a quantity of m(x) on a grid over a rectangle of one plane
// (two latent axes; the other coordinates fixed), as an RGBA PNG with the top row at the rectangle's
// largest second coordinate (so that "up" is +y on screen). The albedo layer is transparent where
// the point is far from the data (predictive variance from render::kFadeFrom to kFadeTo): the
// browser draws its "no data here" hatching there instead of the database mean's colour.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace matlas {
class Model;
class PlausibilityProbe;
}

namespace matlas::server {

enum class MapLayer {
  albedo,    ///< albedo at normal incidence as a colour (sRGB, clamped), transparent where variance is high
  variance,  ///< GP predictive variance (0 at the data .. 1 far away), as a colour ramp
  plausibility,  ///< dimmed albedo where plausible, red by how much the material is not
                 ///< (negative values, albedo outside [0, 1]; manifold/plausibility.h)
};

struct MapLayerRequest {
  MapLayer layer = MapLayer::albedo;
  int axis_x = 0, axis_y = 1;   ///< latent axes shown horizontally and vertically
  Eigen::VectorXd base;         ///< full latent point giving the other coordinates
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;  ///< the rectangle
  int width = 64, height = 64;  ///< grid size (pixel centres sample the rectangle)
};

/// Computes the layer as RGBA pixels (width * height * 4, rows top first). The plausibility layer
/// needs `probe`.
std::vector<unsigned char> map_layer_pixels(const Model& model, const MapLayerRequest& request,
                                            const PlausibilityProbe* probe = nullptr);
/// The same as PNG bytes.
std::string map_layer_png(const Model& model, const MapLayerRequest& request,
                          const PlausibilityProbe* probe = nullptr);

/// The ramp used for the variance layer, t in [0, 1] -> sRGB8.
void variance_colour(double t, unsigned char rgb[3]);

}  // namespace matlas::server
