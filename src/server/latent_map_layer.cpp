#include "server/latent_map_layer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "formats/image_io.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"
#include "render/latent_map.h"

namespace matlas::server {

void variance_colour(double t, unsigned char rgb[3]) {
  // A dark-to-warm ramp (perceptually ordered; dark = certain, near the data).
  static constexpr std::array<std::array<double, 3>, 5> kStops = {{
      {0.05, 0.06, 0.10}, {0.18, 0.16, 0.38}, {0.55, 0.20, 0.45}, {0.92, 0.45, 0.30}, {0.99, 0.90, 0.60}}};
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(t), kStops.size() - 2);
  const double f = t - static_cast<double>(i);
  for (int c = 0; c < 3; ++c) {
    const double v = kStops[i][static_cast<std::size_t>(c)] * (1 - f) + kStops[i + 1][static_cast<std::size_t>(c)] * f;
    rgb[c] = static_cast<unsigned char>(std::lround(255.0 * v));
  }
}

std::string map_layer_png(const Model& model, const MapLayerRequest& r, const PlausibilityProbe* probe) {
  const std::vector<unsigned char> pixels = map_layer_pixels(model, r, probe);
  return encode_png_srgba8(pixels.data(), r.width, r.height);
}

std::vector<unsigned char> map_layer_pixels(const Model& model, const MapLayerRequest& r, const PlausibilityProbe* probe) {
  if (r.layer == MapLayer::plausibility && !probe) throw Error("plausibility layer without a probe (internal error)");
  const auto width = static_cast<std::size_t>(r.width), height = static_cast<std::size_t>(r.height);
  const std::size_t cells = width * height;
  // Every cell's latent point, then its weights and variance in batches (one triangular solve
  // with many right-hand sides), the albedo and plausibility by matrix products.
  Eigen::MatrixXd points(static_cast<Eigen::Index>(cells), r.base.size());
  for (std::size_t row = 0; row < height; ++row)
    for (std::size_t col = 0; col < width; ++col) {
      Eigen::VectorXd x = r.base;
      x[r.axis_x] = r.x0 + (r.x1 - r.x0) * (static_cast<double>(col) + 0.5) / static_cast<double>(width);
      x[r.axis_y] = r.y1 + (r.y0 - r.y1) * (static_cast<double>(row) + 0.5) / static_cast<double>(height);
      points.row(static_cast<Eigen::Index>(row * width + col)) = x.transpose();
    }
  const Model::Prediction predicted = model.predict_batch(points);  // the model's interpolation mode
  const Eigen::VectorXd& variance = predicted.variance;
  Eigen::MatrixXd albedo;
  std::vector<Plausibility> plausibility;
  if (r.layer != MapLayer::variance) {
    albedo = model.albedo_batch(predicted.weights);  // rows 0..2: normal incidence
    if (r.layer == MapLayer::plausibility) plausibility = probe->batch(predicted.weights);
  }
  std::vector<unsigned char> pixels(cells * 4);
  for (std::size_t k = 0; k < cells; ++k) {
    unsigned char* px = pixels.data() + k * 4;
    const auto j = static_cast<Eigen::Index>(k);
    px[3] = 255;
    if (r.layer == MapLayer::variance) {
      variance_colour(variance[j], px);
      continue;
    }
    double shown[3];
    auto albedo_srgb = [&](int c) { return srgb_encode(static_cast<float>(std::clamp(albedo(c, j), 0.0, 1.0))); };
    if (r.layer == MapLayer::albedo) {
      // Transparent where the point is far from the data: what the model returns there is the
      // database mean, not a material.
      for (int c = 0; c < 3; ++c) shown[c] = albedo_srgb(c);
      const double fade = render::uncertainty_fade(variance[j], render::kFadeFrom, render::kFadeTo);
      px[3] = static_cast<unsigned char>(std::lround(255.0 * (1.0 - fade)));
    } else {
      // Plausible: the albedo, dimmed. Not plausible: red, brighter the larger the violation.
      const double violation = plausibility[k].violation();
      const double t = violation > 0 ? 0.45 + 0.55 * std::clamp(violation / 0.3, 0.0, 1.0) : 0.0;
      static constexpr double kRed[3] = {0.95, 0.16, 0.12};
      for (int c = 0; c < 3; ++c) shown[c] = (1.0 - t) * 0.45 * albedo_srgb(c) + t * kRed[c];
    }
    for (int c = 0; c < 3; ++c) px[c] = static_cast<unsigned char>(std::lround(255.0 * shown[c]));
  }
  return pixels;
}

}  // namespace matlas::server
