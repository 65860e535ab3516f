#include "server/latent_map_layer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/parallel.h"
#include "formats/image_io.h"
#include "manifold/model.h"

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

std::string map_layer_png(const Model& model, const MapLayerRequest& r) {
  const auto width = static_cast<std::size_t>(r.width), height = static_cast<std::size_t>(r.height);
  std::vector<unsigned char> pixels(width * height * 3);
  parallel_for(0, height, [&](std::size_t row0, std::size_t row1) {
    Eigen::VectorXd x = r.base;
    for (std::size_t row = row0; row < row1; ++row) {
      x[r.axis_y] = r.y1 + (r.y0 - r.y1) * (static_cast<double>(row) + 0.5) / static_cast<double>(height);
      for (std::size_t col = 0; col < width; ++col) {
        x[r.axis_x] = r.x0 + (r.x1 - r.x0) * (static_cast<double>(col) + 0.5) / static_cast<double>(width);
        unsigned char* px = pixels.data() + (row * width + col) * 3;
        if (r.layer == MapLayer::variance) {
          variance_colour(model.variance(x), px);
        } else {
          // Faded towards the map's background where the GP is uncertain (far from the data).
          const Rgb a = model.albedo_curve(model.weights(x)).front();
          const double confidence = 1.0 - 0.8 * std::clamp(model.variance(x), 0.0, 1.0);
          for (int c = 0; c < 3; ++c) {
            const double shown = confidence * srgb_encode(static_cast<float>(std::clamp(a[c], 0.0, 1.0))) +
                                 (1.0 - confidence) * 0.07;
            px[c] = static_cast<unsigned char>(std::lround(255.0 * shown));
          }
        }
      }
    }
  }, 4);
  return encode_png_srgb8(pixels.data(), r.width, r.height);
}

}  // namespace matlas::server
