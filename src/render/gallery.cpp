#include "render/gallery.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "manifold/model.h"
#include "render/image_basis.h"
#include "render/material.h"
#include "render/render.h"
#include "render/sampling.h"
#include "render/text.h"

namespace matlas::render {

std::vector<GalleryEntry> pick_gallery(const Model& model, const GalleryOptions& o) {
  const int n = model.count();
  if (o.random < 0 || o.real < 0 || o.random + o.real == 0) throw Error("gallery: nothing to show");
  if (o.real > n) throw Error("gallery: --real " + std::to_string(o.real) + " exceeds the " + std::to_string(n) + " materials");
  const Eigen::MatrixXd& X = model.latent();
  SampleStream rng(o.seed, 0x9a11e7, 0);
  std::vector<GalleryEntry> entries;
  // Real materials: a random subset.
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  for (int i = n - 1; i > 0; --i) std::swap(order[static_cast<std::size_t>(i)], order[static_cast<std::size_t>(rng.next() * (i + 1))]);
  for (int k = 0; k < o.real; ++k) {
    const int i = order[static_cast<std::size_t>(k)];
    entries.push_back({true, model.names()[static_cast<std::size_t>(i)], X.row(i).transpose(), 0.0});
  }
  // Generated: between a material and one of its nearest neighbours, low variance.
  for (int k = 0; k < o.random; ++k) {
    GalleryEntry best;
    best.variance = 1e300;
    for (int attempt = 0; attempt < 64; ++attempt) {
      const int i = std::min(n - 1, static_cast<int>(rng.next() * n));
      std::vector<std::pair<double, int>> near;
      for (int j = 0; j < n; ++j)
        if (j != i) near.push_back({(X.row(j) - X.row(i)).squaredNorm(), j});
      std::sort(near.begin(), near.end());
      const int pick = near.empty() ? i : near[static_cast<std::size_t>(rng.next() * std::min<std::size_t>(3, near.size()))].second;
      const double t = 0.2 + 0.6 * rng.next();
      const Eigen::VectorXd x = ((1 - t) * X.row(i) + t * X.row(pick)).transpose();
      const double var = model.variance(x);
      if (var < best.variance) best = {false, "generated", x, var};
      if (var <= o.max_variance) break;
    }
    entries.push_back(best);
  }
  for (std::size_t i = entries.size() - 1; i > 0; --i)
    std::swap(entries[i], entries[static_cast<std::size_t>(rng.next() * static_cast<double>(i + 1))]);
  return entries;
}

Image render_gallery(const Model& model, const std::vector<GalleryEntry>& entries, const Scene* scene,
                     const RenderSettings* settings, const ImageBasis* basis, ProgressSink& progress) {
  if (entries.empty()) throw Error("gallery: no entries");
  if (!basis && (!scene || !settings)) throw Error("gallery: needs an image basis or a scene and settings");
  const int w = basis ? basis->width() : settings->width, h = basis ? basis->height() : settings->height;
  const int count = static_cast<int>(entries.size());
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const int rows = (count + cols - 1) / cols;
  const int gap = std::max(2, w / 64);
  Image grid(cols * w + (cols + 1) * gap, rows * h + (rows + 1) * gap);
  std::fill(grid.rgb.begin(), grid.rgb.end(), 0.02f);
  ProgressTask task(progress, "gallery", static_cast<std::uint64_t>(count));
  for (int k = 0; k < count; ++k) {
    const GalleryEntry& e = entries[static_cast<std::size_t>(k)];
    const Eigen::VectorXd weights = e.real ? model.material_weights(model.index_of(e.name)) : model.weights(e.x);
    Image cell;
    if (basis) {
      cell = basis->compose(weights);
    } else {
      cell = render(*scene, ModelMaterial(model, weights), *settings);
    }
    const int ox = gap + (k % cols) * (w + gap), oy = gap + (k / cols) * (h + gap);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) grid.pixel(ox + x, oy + y)[c] = cell.pixel(x, y)[c];
    draw_text(grid, ox + gap, oy + gap, std::to_string(k + 1), std::max(12.0f, static_cast<float>(h) / 12.0f),
              Rgb::Constant(1.0));
    task.advance();
  }
  return grid;
}

nlohmann::json gallery_key(const std::vector<GalleryEntry>& entries) {
  nlohmann::json key = nlohmann::json::array();
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const GalleryEntry& e = entries[k];
    key.push_back({{"cell", k + 1},
                   {"real", e.real},
                   {"name", e.name},
                   {"x", std::vector<double>(e.x.data(), e.x.data() + e.x.size())},
                   {"variance", e.variance}});
  }
  return key;
}

}  // namespace matlas::render
