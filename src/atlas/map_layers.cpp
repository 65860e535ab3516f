#include "atlas/map_layers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "formats/image_io.h"

namespace matlas::atlas {

namespace {

constexpr std::array<MapLayer, 4> kLayers = {MapLayer::albedo, MapLayer::variance, MapLayer::plausibility,
                                             MapLayer::image};

const Eigen::Array3d kImplausibleSrgb(0.95, 0.16, 0.12);

/// sRGB in [0, 1] -> linear.
Eigen::Array3d linear_of(const Eigen::Array3d& srgb) {
  Eigen::Array3d c;
  for (int k = 0; k < 3; ++k) c[k] = srgb_decode(static_cast<float>(srgb[k]));
  return c;
}

/// The albedo at normal incidence of every column of W (3 x m): the first angle of
/// Model::albedo_batch, without the other angles' products.
Eigen::MatrixXd normal_albedo(const Model& model, const Eigen::MatrixXd& W) {
  const auto curves = model.material_albedo().leftCols<3>();  // n x 3: [theta 0][channel]
  const Eigen::RowVector3d mean = curves.colwise().mean();
  Eigen::MatrixXd a = (curves.rowwise() - mean).transpose() * W;
  a.colwise() += mean.transpose();
  return a;
}

/// The violation (Plausibility::violation) of the columns of W that `needed` marks, 0 for the
/// others: probe.batch of the marked columns, in blocks, in parallel (each block's products stay
/// small: the whole grid's sampled values and albedo curves would be 70 MB of fresh memory).
std::vector<double> violations_of(const PlausibilityProbe& probe, const Eigen::MatrixXd& W,
                                  const std::vector<char>& needed) {
  MATLAS_CHECK_EQ(needed.size(), static_cast<std::size_t>(W.cols()));
  std::vector<Eigen::Index> columns;
  for (std::size_t j = 0; j < needed.size(); ++j)
    if (needed[j]) columns.push_back(static_cast<Eigen::Index>(j));
  constexpr std::size_t kBlock = 512;
  const std::size_t blocks = (columns.size() + kBlock - 1) / kBlock;
  std::vector<double> out(needed.size(), 0.0);
  parallel_for_each(0, blocks, [&](std::size_t block) {
    const std::size_t first = block * kBlock, count = std::min(kBlock, columns.size() - first);
    const std::vector<Eigen::Index> part(columns.begin() + static_cast<std::ptrdiff_t>(first),
                                         columns.begin() + static_cast<std::ptrdiff_t>(first + count));
    const std::vector<Plausibility> p = probe.batch(W(Eigen::all, part));
    for (std::size_t k = 0; k < count; ++k) out[static_cast<std::size_t>(part[k])] = p[k].violation();
  });
  return out;
}

}  // namespace

const char* to_string(MapLayer layer) {
  switch (layer) {
    case MapLayer::albedo: return "albedo";
    case MapLayer::variance: return "variance";
    case MapLayer::plausibility: return "plausibility";
    case MapLayer::image: return "image";
  }
  return "?";
}

MapLayer map_layer_from_name(const std::string& name, const std::string& what) {
  for (MapLayer l : kLayers)
    if (name == to_string(l)) return l;
  throw Error(what + " '" + name + "': expected albedo, variance, plausibility or image");
}

const char* far_from_data(Interpolation mode) {
  return mode == Interpolation::convex ? "a mix of the nearest materials" : "only the database mean";
}

double uncertainty_fade(double variance, double from, double to) {
  if (!(to > from)) return variance >= from ? 1.0 : 0.0;
  const double t = std::clamp((variance - from) / (to - from), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

Eigen::Array3d unknown_colour(int x, int y) {
  // sRGB 0.46 grey with 2-pixel dark diagonals every 9 pixels.
  const bool line = ((x + y) % 9 + 9) % 9 < 2;
  return Eigen::Array3d::Constant(line ? 0.035 : 0.18);
}

Eigen::Array3d colour_map(double t) {
  // A dark-to-warm ramp at 5 sRGB stops, interpolated in sRGB (web/src/style.css draws the same
  // stops as the legend's swatch), then linearised.
  static constexpr std::array<std::array<double, 3>, 5> kStops = {
      {{0.05, 0.06, 0.10}, {0.18, 0.16, 0.38}, {0.55, 0.20, 0.45}, {0.92, 0.45, 0.30}, {0.99, 0.90, 0.60}}};
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(t), kStops.size() - 2);
  const double f = t - static_cast<double>(i);
  Eigen::Array3d srgb;
  for (std::size_t c = 0; c < 3; ++c) srgb[static_cast<Eigen::Index>(c)] = kStops[i][c] * (1 - f) + kStops[i + 1][c] * f;
  return linear_of(srgb);
}

Eigen::Array3d implausible_colour() { return linear_of(kImplausibleSrgb); }

Interpolation layer_interpolation(const Model& model, MapLayer layer) {
  return layer == MapLayer::variance ? Interpolation::gp : model.interpolation();
}

bool plausible_by_construction(const Model& model, const PlausibilityProbe* probe) {
  return model.interpolation() == Interpolation::convex && probe != nullptr && probe->inputs_plausible();
}

bool layer_fades(const Model& model, MapLayer layer) {
  return layer == MapLayer::albedo || layer == MapLayer::image ||
         (layer == MapLayer::plausibility && layer_interpolation(model, layer) == Interpolation::convex);
}

double layer_projected_below(const Model& model, MapLayer layer, const LayerStyle& style) {
  return layer_fades(model, layer) ? style.fade_to : std::numeric_limits<double>::infinity();
}

LayerCells layer_cells(const Model& model, const LatentGrid& grid, MapLayer layer, const LayerStyle& style,
                       const PlausibilityProbe* probe) {
  MATLAS_CHECK(layer != MapLayer::image, "the image layer is composed from a basis, not coloured per cell");
  MATLAS_CHECK(layer != MapLayer::plausibility || probe != nullptr, "a plausibility layer has a probe");
  const auto cells = static_cast<std::size_t>(grid.points.rows());
  MATLAS_CHECK(grid.weights.cols() == grid.points.rows() && grid.variance.size() == grid.points.rows(),
               "a weight column and a variance per grid cell");
  LayerCells out;
  out.colour.resize(cells);
  out.fade.assign(cells, 0.0);
  // The albedo and plausibility by matrix products over all cells at once.
  const bool by_construction = layer == MapLayer::plausibility && plausible_by_construction(model, probe);
  const bool fades = layer_fades(model, layer);
  if (fades)
    for (std::size_t k = 0; k < cells; ++k)
      out.fade[k] = uncertainty_fade(grid.variance[static_cast<Eigen::Index>(k)], style.fade_from, style.fade_to);
  Eigen::MatrixXd albedo;
  std::vector<double> violation(cells, 0.0);
  if (layer != MapLayer::variance) {
    albedo = normal_albedo(model, grid.weights);
    if (layer == MapLayer::plausibility && !by_construction) {
      // The probe only where it can change what is seen: not under a full fade, and not where
      // the weights combine plausible inputs convexly (plausible as they are).
      std::vector<char> needed(cells);
      parallel_for(0, cells, [&](std::size_t lo, std::size_t hi) {
        for (std::size_t k = lo; k < hi; ++k)
          needed[k] = out.fade[k] < 1.0 && !probe->plausible_by_construction(grid.weights.col(static_cast<Eigen::Index>(k)));
      });
      violation = violations_of(*probe, grid.weights, needed);
    }
    MATLAS_CHECK(albedo.rows() >= 3 && albedo.cols() == grid.weights.cols(), "an albedo column per cell");
  }
  for (std::size_t k = 0; k < cells; ++k) {
    const auto j = static_cast<Eigen::Index>(k);
    if (layer == MapLayer::variance) {
      out.colour[k] = colour_map(grid.variance[j]);
      continue;
    }
    const Eigen::Array3d a = (albedo.block<3, 1>(0, j).array() * style.albedo_gain).max(0.0).min(1.0);
    if (layer == MapLayer::albedo) {
      out.colour[k] = a;
    } else {
      // Plausible: the albedo, dimmed. Not plausible: red, brighter the larger the violation
      // (mixed in sRGB).
      const double v = violation[k];
      const double t = v > 0 ? 0.45 + 0.55 * std::clamp(v / 0.3, 0.0, 1.0) : 0.0;
      Eigen::Array3d srgb;
      for (int c = 0; c < 3; ++c) srgb[c] = srgb_encode(static_cast<float>(a[c]));
      out.colour[k] = linear_of((1.0 - t) * 0.45 * srgb + t * kImplausibleSrgb);
    }
  }
  return out;
}

std::vector<unsigned char> map_layer_pixels(const Model& model, const LatentPlane& plane, int width, int height,
                                            MapLayer layer, const PlausibilityProbe* probe) {
  const LayerCells cells = layer_cells(model,
                  latent_grid(model, plane, width, height, layer_interpolation(model, layer),
                              layer_projected_below(model, layer, {})),
                  layer, {}, probe);
  std::vector<unsigned char> pixels(cells.colour.size() * 4);
  for (std::size_t k = 0; k < cells.colour.size(); ++k) {
    unsigned char* px = pixels.data() + k * 4;
    for (int c = 0; c < 3; ++c)
      px[c] = static_cast<unsigned char>(std::lround(255.0 * srgb_encode(static_cast<float>(cells.colour[k][c]))));
    px[3] = static_cast<unsigned char>(std::lround(255.0 * (1.0 - cells.fade[k])));
  }
  return pixels;
}

std::string map_layer_png(const Model& model, const LatentPlane& plane, int width, int height, MapLayer layer,
                          const PlausibilityProbe* probe) {
  const std::vector<unsigned char> pixels = map_layer_pixels(model, plane, width, height, layer, probe);
  return encode_png_srgba8(pixels.data(), width, height);
}

}  // namespace matlas::atlas
