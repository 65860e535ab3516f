#include "eval/layout_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <numeric>
#include <random>
#include <set>

#include "core/error.h"
#include "core/parallel.h"
#include "eval/combination_pass.h"
#include "eval/gram_space.h"
#include "eval/pca_baseline.h"
#include "eval/statistics.h"
#include "gp/convex_weights.h"

namespace matlas::eval {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Evenly spread indices: count of 0..n-1 (all when count <= 0 or >= n).
std::vector<int> spread_indices(int n, int count) {
  std::vector<int> idx;
  if (count <= 0 || count >= n) {
    idx.resize(static_cast<std::size_t>(n));
    std::iota(idx.begin(), idx.end(), 0);
    return idx;
  }
  for (int k = 0; k < count; ++k) idx.push_back(static_cast<int>((static_cast<long>(k) * n) / count));
  return idx;
}

double mean_of(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN()
                   : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace

int automatic_stride(std::size_t tables, std::size_t values_per_table, double budget) {
  const double total = static_cast<double>(tables) * static_cast<double>(values_per_table);
  if (!(budget > 0) || total <= budget) return 1;
  return static_cast<int>(std::min(1e6, std::ceil(total / budget)));
}

std::vector<LayoutTransform> all_layouts() {
  std::vector<LayoutTransform> layouts;
  for (bool cosine : {false, true})
    for (auto map : {LayoutTransform::Map::linear, LayoutTransform::Map::cube_root, LayoutTransform::Map::log}) {
      LayoutTransform t;
      t.map = map;
      t.cosine_weighted = cosine;
      layouts.push_back(t);
    }
  return layouts;
}

std::vector<std::pair<int, int>> choose_pairs(int n, int count, unsigned seed) {
  std::vector<std::pair<int, int>> all;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) all.emplace_back(i, j);
  std::mt19937 rng(seed);
  // Fisher-Yates with our own index draws (std::uniform_int_distribution differs across libraries).
  for (std::size_t k = all.size(); k > 1; --k) std::swap(all[k - 1], all[rng() % k]);
  if (count >= 0 && static_cast<std::size_t>(count) < all.size()) all.resize(static_cast<std::size_t>(count));
  std::sort(all.begin(), all.end());
  return all;
}

const ConfigResult& StudyResult::config(const LayoutTransform& layout, int dim) const {
  for (const auto& c : configs)
    if (c.layout.map == layout.map && c.layout.cosine_weighted == layout.cosine_weighted && c.dim == dim)
      return c;
  throw Error("no evaluation result for layout " + layout.to_string() + " and q = " + std::to_string(dim));
}

StudyResult run_layout_study(const MaterialSet& set, const StudyOptions& options, ProgressSink& progress) {
  const int n = static_cast<int>(set.size());
  if (n < 3) throw Error("evaluation needs at least 3 materials (got " + std::to_string(n) + ")");
  if (options.dims.empty()) throw Error("--dims: no latent dimension given");
  for (int q : options.dims)
    if (q < 1 || q > 10) throw Error("--dims: latent dimension " + std::to_string(q) + " is outside 1..10");
  if (options.layouts.empty()) throw Error("no layout transform to evaluate");
  if (options.path_segments < 1) throw Error("path segments must be >= 1");

  StudyResult result;
  result.names = set.names();
  result.dims = options.dims;
  result.layouts = options.layouts;

  // --- Gram matrices, one pass per layout transform ---
  auto t0 = Clock::now();
  Eigen::MatrixXd linear_gram;
  std::vector<Eigen::MatrixXd> layout_grams;
  for (const LayoutTransform& layout : options.layouts) {
    progress.message("Gram matrices for layout " + layout.to_string());
    GramResult g = accumulate_gram(set, layout, options.block_columns, progress);
    if (linear_gram.size() == 0) {
      linear_gram = g.gram;
      result.kept_columns = g.kept_columns;
    }
    layout_grams.push_back(std::move(g.layout_gram));
  }
  result.gram_seconds = seconds_since(t0);
  const double columns = static_cast<double>(result.kept_columns);

  // --- Latent fits: per config, all materials plus one per left-out material ---
  const std::vector<int> held = spread_indices(n, options.materials);
  const std::size_t H = held.size();
  const std::size_t L = options.layouts.size(), Q = options.dims.size();
  result.configs.resize(L * Q);
  std::vector<std::vector<GramProjection>> projections(L * Q, std::vector<GramProjection>(H));
  std::vector<std::vector<double>> reference_residual(L, std::vector<double>(H));
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t k = 0; k < H; ++k) {
      const int h = held[k];
      const std::vector<int> subset = indices_without(n, h);
      const Eigen::VectorXd mean_only = raw_from_centred(Eigen::VectorXd::Zero(n - 1), subset, n);
      reference_residual[l][k] = residual_squared(layout_grams[l], mean_only, h);
    }
  t0 = Clock::now();
  {
    const std::size_t jobs_per_config = 1 + H;
    ProgressTask fits(progress, "fitting latent maps", L * Q * jobs_per_config);
    std::mutex fits_mutex;  // ProgressTask counts from one thread at a time
    std::vector<double> job_seconds(L * Q * jobs_per_config, 0.0);
    parallel_for(0, L * Q * jobs_per_config, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t job = lo; job < hi; ++job) {
        const auto start = Clock::now();
        const std::size_t c = job / jobs_per_config, k = job % jobs_per_config;
        const std::size_t l = c / Q;
        const int q = options.dims[c % Q];
        ConfigResult& config = result.configs[c];
        if (k == 0) {
          const LatentFit fit = fit_latent(layout_grams[l], columns, q, options.fit);
          config.layout = options.layouts[l];
          config.dim = q;
          config.latent = fit.latent();
          config.log_likelihood = fit.log_likelihood;
        } else {
          const int h = held[k - 1];
          const std::vector<int> subset = indices_without(n, h);
          const LatentFit fit = fit_latent(centred_subset_gram(layout_grams[l], subset), columns, q, options.fit);
          projections[c][k - 1] = project_in_gram(fit, subset, layout_grams[l], h, options.projection_starts);
        }
        job_seconds[job] = seconds_since(start);
        {
          std::lock_guard lock(fits_mutex);
          fits.advance();
        }
      }
    });
    for (std::size_t c = 0; c < L * Q; ++c)
      for (std::size_t k = 0; k < jobs_per_config; ++k)
        result.configs[c].fit_seconds += job_seconds[c * jobs_per_config + k];
  }
  result.fit_seconds = seconds_since(t0);

  // --- Items (affine combinations) and the distances wanted between them ---
  std::vector<Eigen::VectorXd> items;
  std::vector<std::pair<int, int>> pairs;
  auto add_item = [&](Eigen::VectorXd c) {
    items.push_back(std::move(c));
    return static_cast<int>(items.size() - 1);
  };
  for (int i = 0; i < n; ++i) add_item(Eigen::VectorXd::Unit(n, i));
  Eigen::MatrixXi material_pair(n, n);
  material_pair.setConstant(-1);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      material_pair(i, j) = material_pair(j, i) = static_cast<int>(pairs.size());
      pairs.emplace_back(i, j);
    }
  // PCA reconstructions, per q and left-out material.
  std::vector<std::vector<int>> pca_pair(Q, std::vector<int>(H));
  for (std::size_t qi = 0; qi < Q; ++qi)
    for (std::size_t k = 0; k < H; ++k) {
      const int h = held[k];
      const std::vector<int> subset = indices_without(n, h);
      const int item = add_item(pca_reconstruction(linear_gram, subset, h, options.dims[qi]));
      pca_pair[qi][k] = static_cast<int>(pairs.size());
      pairs.emplace_back(item, h);
    }
  // matlas reconstructions and latent paths, per config.
  const std::vector<std::pair<int, int>> path_pairs = choose_pairs(n, options.pairs, options.seed);
  std::vector<std::vector<int>> loo_pair(L * Q, std::vector<int>(H));
  // Each projection's candidates; the reported reconstruction is the candidate with the smallest
  // cube-root distance to the held-out table (the projection has that table, as `matlas project`
  // has the user's): the layout metric's optimum is not the perceptual one for mixtures.
  std::vector<std::vector<std::vector<int>>> loo_candidates(L * Q, std::vector<std::vector<int>>(H));
  std::vector<std::vector<std::vector<int>>> step_pair(L * Q);
  const std::vector<int> everyone = indices_without(n, -1);
  for (std::size_t c = 0; c < L * Q; ++c) {
    for (std::size_t k = 0; k < H; ++k) {
      const int item = add_item(projections[c][k].coefficients);
      loo_pair[c][k] = static_cast<int>(pairs.size());
      pairs.emplace_back(item, held[k]);
      for (const Eigen::VectorXd& candidate : projections[c][k].candidates) {
        loo_candidates[c][k].push_back(static_cast<int>(pairs.size()));
        pairs.emplace_back(add_item(candidate), held[k]);
      }
    }
    const ConfigResult& config = result.configs[c];
    const gp::GpPosterior posterior(config.latent, gp::Kernel{1.0, options.fit.nugget});
    const std::size_t layout_index = c / Q;
    std::unique_ptr<gp::ConvexProjection> convex;
    if (options.fit.convex_ridge > 0)
      convex = std::make_unique<gp::ConvexProjection>(layout_grams[layout_index], options.fit.convex_ridge);
    step_pair[c].resize(path_pairs.size());
    for (std::size_t p = 0; p < path_pairs.size(); ++p) {
      const auto [a, b] = path_pairs[p];
      const Eigen::VectorXd xa = config.latent.row(a).transpose(), xb = config.latent.row(b).transpose();
      int previous = a;
      for (int s = 1; s <= options.path_segments; ++s) {
        int next = b;
        if (s < options.path_segments) {
          const double t = static_cast<double>(s) / options.path_segments;
          const Eigen::VectorXd x = (1.0 - t) * xa + t * xb;
          const Eigen::VectorXd w = posterior.weights(x);
          next = add_item(raw_from_weights(convex ? convex->from_centred(w) : w, everyone, n));
        }
        step_pair[c][p].push_back(static_cast<int>(pairs.size()));
        pairs.emplace_back(previous, next);
        previous = next;
      }
    }
  }

  // --- One streaming pass for every perceptual distance ---
  t0 = Clock::now();
  CombinationQuery query;
  query.coefficients.resize(static_cast<Eigen::Index>(items.size()), n);
  for (std::size_t i = 0; i < items.size(); ++i) query.coefficients.row(static_cast<Eigen::Index>(i)) = items[i].transpose();
  query.pairs = pairs;
  query.value_stride = options.value_stride > 0 ? options.value_stride
                                                : automatic_stride(items.size(), 3 * set.dims().bins(),
                                                                   options.compared_values_budget);
  result.value_stride = query.value_stride;
  progress.message("perceptual distances: " + std::to_string(items.size()) + " tables, " +
                   std::to_string(pairs.size()) + " pairs, every " +
                   (query.value_stride == 1 ? std::string("value") : std::to_string(query.value_stride) + "th value") +
                   (options.value_stride > 0 ? "" : " (--stride 1 for all)"));
  const CombinationResult pass = evaluate_combinations(set, query, progress);
  result.pass_seconds = seconds_since(t0);
  result.compared_values = pass.values;

  result.material_cbrt = Eigen::MatrixXd::Zero(n, n);
  result.material_rmse = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j) {
        const BrdfDistance& d = pass.distances[static_cast<std::size_t>(material_pair(i, j))];
        result.material_cbrt(i, j) = d.cbrt_cosine;
        result.material_rmse(i, j) = d.cosine_rmse;
      }

  // --- Per config summaries ---
  for (std::size_t c = 0; c < L * Q; ++c) {
    ConfigResult& config = result.configs[c];
    const std::size_t qi = c % Q;
    std::vector<double> gp_c, gp_r, pca_c, pca_r, nn_c, nn_r;
    for (std::size_t k = 0; k < H; ++k) {
      const int h = held[k];
      LooEntry e;
      e.material = h;
      e.gp = pass.distances[static_cast<std::size_t>(loo_pair[c][k])];
      for (const int pair : loo_candidates[c][k])
        if (pass.distances[static_cast<std::size_t>(pair)].cbrt_cosine < e.gp.cbrt_cosine)
          e.gp = pass.distances[static_cast<std::size_t>(pair)];
      e.pca = pass.distances[static_cast<std::size_t>(pca_pair[qi][k])];
      double best = std::numeric_limits<double>::infinity();
      for (int j = 0; j < n; ++j)
        if (j != h && result.material_cbrt(h, j) < best) best = result.material_cbrt(h, j), e.nearest_material = j;
      e.nearest = pass.distances[static_cast<std::size_t>(material_pair(h, e.nearest_material))];
      const double ref = reference_residual[c / Q][k];
      e.gram_residual = ref > 0 ? projections[c][k].residual_squared / ref : 0.0;
      gp_c.push_back(e.gp.cbrt_cosine), gp_r.push_back(e.gp.cosine_rmse);
      pca_c.push_back(e.pca.cbrt_cosine), pca_r.push_back(e.pca.cosine_rmse);
      nn_c.push_back(e.nearest.cbrt_cosine), nn_r.push_back(e.nearest.cosine_rmse);
      config.loo.push_back(e);
    }
    config.loo_gp_cbrt = mean_of(gp_c), config.loo_gp_rmse = mean_of(gp_r);
    config.loo_pca_cbrt = mean_of(pca_c), config.loo_pca_rmse = mean_of(pca_r);
    config.loo_nearest_cbrt = mean_of(nn_c), config.loo_nearest_rmse = mean_of(nn_r);

    std::vector<double> latent_d, perceptual_d;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        latent_d.push_back((config.latent.row(i) - config.latent.row(j)).norm());
        perceptual_d.push_back(result.material_cbrt(i, j));
      }
    config.spearman_pairs = spearman(latent_d, perceptual_d);

    std::vector<double> step_latent, step_perceptual, ratios, unevenness;
    for (std::size_t p = 0; p < path_pairs.size(); ++p) {
      PathEntry e;
      e.a = path_pairs[p].first, e.b = path_pairs[p].second;
      e.latent_distance = (config.latent.row(e.a) - config.latent.row(e.b)).norm();
      e.ends = pass.distances[static_cast<std::size_t>(material_pair(e.a, e.b))];
      double length = 0, largest = 0;
      for (int id : step_pair[c][p]) {
        const BrdfDistance& d = pass.distances[static_cast<std::size_t>(id)];
        e.steps.push_back(d);
        step_latent.push_back(e.latent_distance / options.path_segments);
        step_perceptual.push_back(d.cbrt_cosine);
        length += d.cbrt_cosine;
        largest = std::max(largest, d.cbrt_cosine);
      }
      if (e.ends.cbrt_cosine > 0) ratios.push_back(length / e.ends.cbrt_cosine);
      if (length > 0) unevenness.push_back(largest / (length / options.path_segments));
      config.paths.push_back(std::move(e));
    }
    config.spearman_steps = step_latent.size() >= 2 ? spearman(step_latent, step_perceptual)
                                                    : std::numeric_limits<double>::quiet_NaN();
    config.path_length_ratio = mean_of(ratios);
    config.path_step_unevenness = mean_of(unevenness);
  }

  // --- Recommendation: lowest leave-one-out cube-root error averaged over the dims ---
  std::vector<std::pair<double, std::size_t>> score;
  for (std::size_t l = 0; l < L; ++l) {
    double loo = 0, rho = 0;
    for (std::size_t qi = 0; qi < Q; ++qi) {
      loo += result.configs[l * Q + qi].loo_gp_cbrt / static_cast<double>(Q);
      rho += result.configs[l * Q + qi].spearman_pairs / static_cast<double>(Q);
    }
    score.emplace_back(H > 0 ? loo : -rho, l);
  }
  std::sort(score.begin(), score.end());
  result.recommended = options.layouts[score.front().second];
  char text[512];
  if (H > 0 && L > 1) {
    std::snprintf(text, sizeof text,
                  "%s: lowest leave-one-out cube-root error averaged over q (%.4f; next best %s: %.4f)",
                  result.recommended.to_string().c_str(), score[0].first,
                  options.layouts[score[1].second].to_string().c_str(), score[1].first);
  } else if (H > 0) {
    std::snprintf(text, sizeof text, "%s: the only layout evaluated (leave-one-out cube-root error %.4f)",
                  result.recommended.to_string().c_str(), score[0].first);
  } else {
    std::snprintf(text, sizeof text, "%s: highest latent/perceptual rank correlation averaged over q (%.3f)",
                  result.recommended.to_string().c_str(), -score[0].first);
  }
  result.recommendation = text;
  return result;
}

}  // namespace matlas::eval
