#include "atlas/gallery.h"
#include "atlas/sampling_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "atlas/model_material.h"
#include "core/check.h"
#include "core/error.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"
#include "render/image_basis.h"
#include "render/material.h"
#include "render/progressive_render.h"
#include "render/render.h"
#include "render/sampling.h"
#include "render/text.h"

namespace matlas::atlas {

using render::draw_text;
using render::SampleStream;

namespace {

constexpr double kLuma[3] = {0.2126, 0.7152, 0.0722};

/// Farthest-point sampling: repeatedly the row of F (among `allowed`) farthest from everything
/// chosen so far, starting from distances `nearest` (infinity where nothing is chosen yet; then
/// `first` is taken first). Returns the chosen rows in order.
std::vector<int> farthest_points(const Eigen::MatrixXd& F, const std::vector<int>& allowed, Eigen::VectorXd nearest,
                                 int count, int first) {
  MATLAS_CHECK_EQ(nearest.size(), F.rows());
  MATLAS_CHECK_LT(first, static_cast<int>(F.rows()));
  std::vector<int> chosen;
  std::vector<bool> used(static_cast<std::size_t>(F.rows()), false);
  for (int k = 0; k < count && k < static_cast<int>(allowed.size()); ++k) {
    int best = -1;
    if (k == 0 && first >= 0 && !std::isfinite(nearest[first])) {
      best = first;
    } else {
      double far = -1;
      for (int i : allowed)
        if (!used[static_cast<std::size_t>(i)] && nearest[i] > far) far = nearest[i], best = i;
    }
    if (best < 0) break;
    used[static_cast<std::size_t>(best)] = true;
    chosen.push_back(best);
    for (int i : allowed) nearest[i] = std::min(nearest[i], (F.row(i) - F.row(best)).norm());
  }
  return chosen;
}

double min_distance_to(const Eigen::RowVectorXd& f, const Eigen::MatrixXd& set, int skip = -1) {
  double d = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < set.rows(); ++i)
    if (i != skip) d = std::min(d, (set.row(i) - f).norm());
  return d;
}

}  // namespace

AppearanceFeatures::AppearanceFeatures(const Model& model) : model_(model) {
  const MerlDims& d = model.dims();
  const int j = std::clamp(static_cast<int>(d.theta_d * 10.0 / 90.0), 0, d.theta_d - 1);
  for (int i = 0; i < std::min(2, d.theta_h); ++i) peak_bins_.push_back(d.flat(i, j, d.phi_d / 2));
  const int n = model.count();
  const Eigen::MatrixXd raw_inputs = raw(Eigen::MatrixXd::Identity(n, n));
  // Spreads with floors, so that a database of one colour does not blow up tiny differences.
  const double floors[kCount] = {0.1, 0.05, 0.05, 0.1};
  for (int k = 0; k < kCount; ++k) {
    const Eigen::VectorXd c = raw_inputs.col(k);
    const double sd = n > 1 ? std::sqrt((c.array() - c.mean()).square().sum() / (n - 1)) : 0.0;
    scale_[k] = std::max(sd, floors[k]);
  }
  materials_ = raw_inputs.array().rowwise() / scale_.transpose().array();
}

Eigen::MatrixXd AppearanceFeatures::raw(const Eigen::MatrixXd& W) const {
  const Eigen::MatrixXd albedo = model_.albedo_batch(W);  // rows 0..2: normal incidence
  Eigen::MatrixXd F(W.cols(), kCount);
  for (Eigen::Index m = 0; m < W.cols(); ++m) {
    const double r = std::max(albedo(0, m), 1e-3), g = std::max(albedo(1, m), 1e-3), b = std::max(albedo(2, m), 1e-3);
    const double lum = std::max(kLuma[0] * r + kLuma[1] * g + kLuma[2] * b, 1e-3);
    double peak = 0;
    for (std::size_t bin : peak_bins_) {
      const Rgb v = model_.bin_rgb(bin, W.col(m));
      peak += (kLuma[0] * v[0] + kLuma[1] * v[1] + kLuma[2] * v[2]) / static_cast<double>(peak_bins_.size());
    }
    F(m, 0) = std::log(lum);
    F(m, 1) = std::log(r / g);
    F(m, 2) = std::log(b / g);
    F(m, 3) = std::log(std::max(kPi * peak, 1e-4) / lum);
  }
  return F;
}

Eigen::MatrixXd AppearanceFeatures::operator()(const Eigen::MatrixXd& W) const {
  return raw(W).array().rowwise() / scale_.transpose().array();
}

namespace {

/// The candidates of generated materials: between each material and its `neighbours` nearest
/// latent neighbours, at jittered fractions 0.15, 0.3, 0.5, 0.7, 0.85 of the way (those near a
/// material are variants of it, those in the middle mixes of two), each pair once.
Eigen::MatrixXd candidate_points(const Eigen::MatrixXd& X, int neighbours, SampleStream& rng) {
  const int n = static_cast<int>(X.rows());
  std::vector<std::pair<int, int>> pairs;
  const int k = std::clamp(neighbours, 1, n - 1);
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, int>> near;
    for (int j = 0; j < n; ++j)
      if (j != i) near.push_back({(X.row(j) - X.row(i)).squaredNorm(), j});
    std::partial_sort(near.begin(), near.begin() + k, near.end());
    for (int t = 0; t < k; ++t) pairs.push_back({std::min(i, near[static_cast<std::size_t>(t)].second),
                                                std::max(i, near[static_cast<std::size_t>(t)].second)});
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  static constexpr double kFractions[] = {0.15, 0.3, 0.5, 0.7, 0.85};
  const int per_pair = 5;
  const int m = static_cast<int>(pairs.size()) * per_pair;
  Eigen::MatrixXd points(m, X.cols());
  for (std::size_t p = 0; p < pairs.size(); ++p)
    for (int s = 0; s < per_pair; ++s) {
      const double t = kFractions[s] + 0.1 * (rng.next() - 0.5);
      const auto c = static_cast<Eigen::Index>(p) * per_pair + s;
      points.row(c) = (1 - t) * X.row(pairs[p].first) + t * X.row(pairs[p].second);
    }
  return points;
}

/// The candidates to choose generated materials from: low variance, plausible (with
/// `plausible_only`) and novel; the filters relaxed from the last one when fewer than `o.random`
/// pass, down to the lowest-variance candidates. Counts what each filter rejected in `stats`.
std::vector<int> candidate_pool(const Eigen::VectorXd& variance, const std::vector<bool>& plausible,
                                const Eigen::VectorXd& novelty, const GalleryOptions& o, GalleryStats& stats) {
  const int m = static_cast<int>(variance.size());
  stats.candidates = m;
  std::vector<int> low, fine, fresh;
  for (int c = 0; c < m; ++c)
    if (variance[c] <= o.max_variance) low.push_back(c);
  for (int c : low)
    if (!o.plausible_only || plausible[static_cast<std::size_t>(c)]) fine.push_back(c);
  for (int c : fine)
    if (novelty[c] >= o.min_novelty) fresh.push_back(c);
  stats.rejected_variance = m - static_cast<int>(low.size());
  stats.rejected_implausible = static_cast<int>(low.size() - fine.size());
  stats.rejected_copies = static_cast<int>(fine.size() - fresh.size());
  std::vector<int> pool = fresh;
  if (static_cast<int>(pool.size()) < o.random) stats.relaxed.push_back("novelty"), pool = fine;
  if (static_cast<int>(pool.size()) < o.random && o.plausible_only) stats.relaxed.push_back("plausibility"), pool = low;
  if (static_cast<int>(pool.size()) < o.random) {
    // Too little near the data: the lowest-variance candidates.
    stats.relaxed.push_back("variance");
    pool.resize(static_cast<std::size_t>(m));
    std::iota(pool.begin(), pool.end(), 0);
    std::stable_sort(pool.begin(), pool.end(), [&](int a, int b) { return variance[a] < variance[b]; });
    pool.resize(static_cast<std::size_t>(std::min(m, std::max(o.random, m / 4))));
  }
  return pool;
}

/// The entries picked so far and their appearance features (one row each).
struct Picked {
  std::vector<GalleryEntry> entries;
  Eigen::MatrixXd features = Eigen::MatrixXd(0, AppearanceFeatures::kCount);
  void add(GalleryEntry e, const Eigen::RowVectorXd& f) {
    entries.push_back(std::move(e));
    features.conservativeResize(features.rows() + 1, Eigen::NoChange);
    features.row(features.rows() - 1) = f;
  }
};

/// Real materials: farthest-point sampling over the database, from a random first one.
void pick_real(const Model& model, const AppearanceFeatures& features, int count, SampleStream& rng, Picked& picked) {
  const int n = model.count();
  const Eigen::MatrixXd& Fm = features.materials();
  const Eigen::MatrixXd raw_m = features.raw(Eigen::MatrixXd::Identity(n, n));
  std::vector<int> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  const int first = std::min(n - 1, static_cast<int>(rng.next() * n));
  const std::vector<int> real =
      farthest_points(Fm, all, Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()), count, first);
  for (int i : real) {
    GalleryEntry e;
    e.real = true;
    e.name = model.names()[static_cast<std::size_t>(i)];
    e.x = model.latent().row(i).transpose();
    for (int c = 0; c < 3; ++c) e.albedo[c] = model.material_albedo()(i, c);
    e.gloss = raw_m(i, 3);
    e.novelty = min_distance_to(Fm.row(i), Fm, i);
    e.max_albedo = model.material_albedo().row(i).maxCoeff();
    picked.add(std::move(e), Fm.row(i));
  }
}

/// Generated materials: plausible, novel candidates near the data (candidate_pool), then
/// farthest-point sampling among them, away from what is picked already.
void pick_generated(const Model& model, const AppearanceFeatures& features, const GalleryOptions& o,
                    SampleStream& rng, GalleryStats& stats, Picked& picked) {
  double input_max_albedo = 0;
  for (int i = 0; i < model.count(); ++i)
    input_max_albedo = std::max(input_max_albedo, model.material_albedo().row(i).maxCoeff());
  const Eigen::MatrixXd points = candidate_points(model.latent(), o.neighbours, rng);
  const int m = static_cast<int>(points.rows());
  // All candidates' weights and variances in one batch (products with K^-1 over blocks of
  // points, convex solves warm-started from the previous candidate, in parallel): the same
  // values as weights() and variance() point by point, which at n = 1000 and ~5n candidates
  // were 5n cold O(n^2) solves in a row.
  Model::Prediction predicted = model.predict_batch(points);
  const Eigen::MatrixXd W = std::move(predicted.weights);
  const Eigen::VectorXd variance = std::move(predicted.variance);
  const Eigen::MatrixXd F = features(W), raw_c = features.raw(W);
  const std::vector<Plausibility> plausibility = PlausibilityProbe(model, 4096).batch(W);
  Eigen::VectorXd novelty(m);
  for (int c = 0; c < m; ++c) novelty[c] = min_distance_to(F.row(c), features.materials());
  auto plausible = [&](int c) {
    const Plausibility& p = plausibility[static_cast<std::size_t>(c)];
    return p.negative_fraction == 0 && p.min_albedo >= 0 && p.max_albedo <= input_max_albedo * (1 + 1e-9);
  };
  std::vector<bool> plausible_flags(static_cast<std::size_t>(m));
  for (int c = 0; c < m; ++c) plausible_flags[static_cast<std::size_t>(c)] = plausible(c);
  std::vector<int> pool = candidate_pool(variance, plausible_flags, novelty, o, stats);
  std::sort(pool.begin(), pool.end());
  Eigen::VectorXd nearest = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
  for (int c : pool) nearest[c] = picked.features.rows() > 0 ? min_distance_to(F.row(c), picked.features) : nearest[c];
  const int start = pool.empty() ? -1 : pool[static_cast<std::size_t>(std::min<double>(pool.size() - 1, rng.next() * pool.size()))];
  for (int c : farthest_points(F, pool, nearest, o.random, start)) {
    GalleryEntry e;
    e.name = "generated";
    e.x = points.row(c).transpose();
    e.variance = variance[c];
    const Eigen::MatrixXd a = model.albedo_batch(W.col(c));
    for (int ch = 0; ch < 3; ++ch) e.albedo[ch] = a(ch, 0);
    e.gloss = raw_c(c, 3);
    e.novelty = novelty[c];
    const Plausibility& p = plausibility[static_cast<std::size_t>(c)];
    e.plausible = plausible(c);
    e.negative_fraction = p.negative_fraction;
    e.max_albedo = p.max_albedo;
    picked.add(std::move(e), F.row(c));
  }
}

/// The smallest distance between two rows (0 for fewer than two).
double min_pair_distance(const Eigen::MatrixXd& rows) {
  double d = std::numeric_limits<double>::infinity();
  for (Eigen::Index a = 0; a < rows.rows(); ++a)
    for (Eigen::Index b = a + 1; b < rows.rows(); ++b) d = std::min(d, (rows.row(a) - rows.row(b)).norm());
  return std::isfinite(d) ? d : 0.0;
}

}  // namespace

std::vector<GalleryEntry> pick_gallery(const Model& model, const GalleryOptions& o, GalleryStats* stats_out) {
  const int n = model.count();
  if (o.random < 0 || o.real < 0 || o.random + o.real == 0) throw Error("gallery: nothing to show");
  if (o.real > n) throw Error("gallery: --real " + std::to_string(o.real) + " exceeds the " + std::to_string(n) + " materials");
  if (o.random > 0 && n < 2) throw Error("gallery: generated materials need at least 2 database materials");
  SampleStream rng(o.seed, 0x9a11e7, 0);
  GalleryStats stats;
  const AppearanceFeatures features(model);
  Picked picked;
  pick_real(model, features, o.real, rng, picked);
  if (o.random > 0) pick_generated(model, features, o, rng, stats, picked);
  stats.min_distance = min_pair_distance(picked.features);
  std::vector<GalleryEntry>& entries = picked.entries;
  for (std::size_t i = entries.size(); i-- > 1;)  // none picked (no plausible candidate): nothing to shuffle
    std::swap(entries[i], entries[static_cast<std::size_t>(rng.next() * static_cast<double>(i + 1))]);
  if (stats_out) *stats_out = stats;
  return std::move(entries);
}

Image render_gallery(const Model& model, const std::vector<GalleryEntry>& entries, const render::Scene* scene,
                     const render::RenderSettings* settings, const render::ImageBasis* basis,
                     ProgressSink& progress, double target_error, std::vector<render::RefinementState>* refined) {
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
  // Every cell through the model's fitted mixture: real and generated cells alike, as in a basis.
  const render::RenderSettings fitted = settings ? model_render_settings(model, *settings) : render::RenderSettings{};
  for (int k = 0; k < count; ++k) {
    const GalleryEntry& e = entries[static_cast<std::size_t>(k)];
    const Eigen::VectorXd weights = e.real ? model.material_weights(model.index_of(e.name)) : model.weights(e.x);
    Image cell;
    if (basis) {
      cell = basis->compose(weights);
    } else if (target_error > 0) {
      render::ProgressiveSettings cell_settings;
      cell_settings.render = fitted;
      cell_settings.render.spp = std::min(16, fitted.spp);
      cell_settings.limits.target_error = target_error;
      cell_settings.limits.max_spp = fitted.spp;
      cell_settings.limits.min_converged_spp = std::min(64, fitted.spp);
      render::ProgressiveRender r(std::shared_ptr<const render::Scene>(scene, [](const render::Scene*) {}),
                                  std::make_shared<const ModelTableMaterial>(model, weights), cell_settings);
      while (!r.refine(1.0).converged) {
      }
      cell = r.image();
      if (refined) refined->push_back(r.state());
    } else {
      cell = render::render(*scene, ModelTableMaterial(model, weights), fitted);  // table built once per cell
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

nlohmann::json gallery_key(const Model& model, const std::vector<GalleryEntry>& entries, const GalleryStats& stats) {
  nlohmann::json cells = nlohmann::json::array();
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const GalleryEntry& e = entries[k];
    cells.push_back({{"cell", k + 1},
                     {"real", e.real},
                     {"name", e.name},
                     {"x", std::vector<double>(e.x.data(), e.x.data() + e.x.size())},
                     {"variance", e.variance},
                     {"albedo", {e.albedo[0], e.albedo[1], e.albedo[2]}},
                     {"gloss", e.gloss},
                     {"novelty", e.novelty},
                     {"plausible", e.plausible},
                     {"negative_fraction", e.negative_fraction},
                     {"max_albedo", e.max_albedo}});
  }
  return {{"interpolation", std::string(to_string(model.interpolation()))},
          {"selection",
           {{"candidates", stats.candidates},
            {"rejected_variance", stats.rejected_variance},
            {"rejected_implausible", stats.rejected_implausible},
            {"rejected_copies", stats.rejected_copies},
            {"relaxed", stats.relaxed},
            {"min_feature_distance", stats.min_distance}}},
          {"cells", cells}};
}

}  // namespace matlas::atlas
