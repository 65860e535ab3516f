#pragma once
// The layers of latent maps, one set for the `matlas map` pictures and the server's map layers:
// what colour each cell of a LatentGrid (latent_plane.h) gets, with one colour ramp and one
// "no data here" fade.
//
// Honesty rule: where the predictive variance says a point is far from the data, the albedo and
// image layers fade out (into a hatched neutral grey in pictures, into transparency in the
// server's layers, where the browser draws its hatching) instead of showing the database mean as
// if it were a material.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "atlas/latent_plane.h"
#include "manifold/plausibility.h"

namespace matlas::atlas {

enum class MapLayer {
  albedo,        ///< albedo at normal incidence (clamped to [0, 1]), fading out where variance is high
  variance,      ///< GP predictive variance (0 at the data .. 1 far away) on the colour ramp
  plausibility,  ///< dimmed albedo where plausible, red by how much the material is not
                 ///< (negative values, albedo outside [0, 1]; manifold/plausibility.h)
  image,         ///< rendered thumbnails composed from an image basis (pictures only)
};

/// "albedo", "variance", "plausibility", "image".
const char* to_string(MapLayer layer);
/// The layer of a name; throws matlas::Error naming `what` (e.g. "--layer") and the choices.
MapLayer map_layer_from_name(const std::string& name, const std::string& what);

/// Default predictive variances where maps start fading into "no data here" and where the fade is
/// complete (the browser uses the same, from GET /api/model).
inline constexpr double kFadeFrom = 0.5, kFadeTo = 0.9;

/// What a point far from the data is, for legends: the database mean under the GP's weights (they
/// fall to 0), a mix of the nearest materials under convex weights (they still sum to 1).
const char* far_from_data(Interpolation mode);

/// How much of "no data here" to show at predictive variance v: 0 below `from`, 1 above `to`,
/// smooth in between.
double uncertainty_fade(double variance, double from, double to);

/// The neutral "no data here" colour at pixel (x, y) (linear RGB): mid grey with dark diagonal
/// hatching, so that it cannot be mistaken for a grey material.
Eigen::Array3d unknown_colour(int x, int y);

/// The colour ramp of the variance layer for t in [0, 1], linear RGB: dark (certain, near the
/// data) to warm, perceptually ordered; its sRGB stops are the browser's legend swatch.
Eigen::Array3d colour_map(double t);

/// The plausibility layer's colour for the largest violations (linear RGB).
Eigen::Array3d implausible_colour();

struct LayerStyle {
  double albedo_gain = 1.0;  ///< albedo and plausibility layers: scale before display
  double fade_from = kFadeFrom, fade_to = kFadeTo;
};

/// The weights a layer needs: the model's mode, but the GP's for the variance layer (which uses
/// none: no convex projection to pay for).
Interpolation layer_interpolation(const Model& model, MapLayer layer);
/// Whether the plausibility layer has nothing to find: convex weights over inputs that are all
/// plausible on the probe's samples (PlausibilityProbe::inputs_plausible). Then the layer is the
/// dimmed albedo and probes no cell.
bool plausible_by_construction(const Model& model, const PlausibilityProbe* probe);

/// Whether a layer fades into "no data here" far from the data: the albedo and image layers, and the
/// plausibility layer of convex weights (there a point is a mix of the nearest materials, as
/// plausible as they are; the GP's weights are shown everywhere).
bool layer_fades(const Model& model, MapLayer layer);

/// The predictive variance from which a layer's cells are not seen (latent_grid's project_below):
/// fade_to for the layers that fade (the cell is all "no data here"), no limit for the others.
double layer_projected_below(const Model& model, MapLayer layer, const LayerStyle& style);

/// The colour of every cell of a grid (albedo, variance or plausibility layer): linear RGB in
/// [0, 1], and how far it fades into "no data here" (0: not at all; the layers that fade are
/// those of layer_projected_below).
struct LayerCells {
  std::vector<Eigen::Array3d> colour;
  std::vector<double> fade;
};
/// The plausibility layer needs `probe`, which it asks only about the cells that are seen (not
/// fully faded) and not plausible by construction (PlausibilityProbe::plausible_by_construction);
/// the image layer is drawn by render_latent_map.
LayerCells layer_cells(const Model& model, const LatentGrid& grid, MapLayer layer, const LayerStyle& style = {},
                       const PlausibilityProbe* probe = nullptr);

/// The server's layer: a width x height grid over the plane (pixel centres sample it, top row at
/// v_max) as RGBA sRGB8 pixels (rows top first), alpha = 1 - fade.
std::vector<unsigned char> map_layer_pixels(const Model& model, const LatentPlane& plane, int width, int height,
                                            MapLayer layer, const PlausibilityProbe* probe = nullptr);
/// The same as PNG bytes.
std::string map_layer_png(const Model& model, const LatentPlane& plane, int width, int height, MapLayer layer,
                          const PlausibilityProbe* probe = nullptr);

}  // namespace matlas::atlas
