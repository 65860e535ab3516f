#include "eval/layout_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <set>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "eval/combination_pass.h"
#include "eval/fit_records.h"
#include "eval/gram_space.h"
#include "eval/pca_baseline.h"
#include "eval/statistics.h"
#include "manifold/gram_reduce.h"
#include "gp/convex_weights.h"

namespace matlas::eval {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
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

int automatic_held_out(std::size_t materials) {
  const int n = static_cast<int>(std::min<std::size_t>(materials, 1u << 30));
  const int count = n <= 50 ? 24 : std::max(8, 1200 / n);
  return std::min(count, n);
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

namespace {

void validate(const MaterialSet& set, const StudyOptions& options) {
  const int n = static_cast<int>(set.size());
  if (n < 3) throw Error("evaluation needs at least 3 materials (got " + std::to_string(n) + ")");
  if (options.dims.empty()) throw Error("--dims: no latent dimension given");
  for (int q : options.dims)
    if (q < 1 || q > 10) throw Error("--dims: latent dimension " + std::to_string(q) + " is outside 1..10");
  if (options.layouts.empty()) throw Error("no layout transform to evaluate");
  if (options.path_segments < 1) throw Error("path segments must be >= 1");
}

/// Every table the study compares (an affine combination of the materials: the materials
/// themselves, PCA and matlas reconstructions, points along latent paths) and every pair of them
/// whose distance it needs, with the pair indices of each role. One streaming pass over the
/// database measures them all (eval/combination_pass.h).
struct DistancePlan {
  std::vector<Eigen::VectorXd> items;
  std::vector<std::pair<int, int>> pairs;
  Eigen::MatrixXi material_pair;              ///< (i, j): the pair of materials i and j
  std::vector<std::vector<int>> pca_pair;     ///< [q][held]: PCA reconstruction vs the material
  std::vector<std::vector<int>> loo_pair;     ///< [config][held]: projection vs the material
  /// [config][held]: each projection candidate vs the material; the reported reconstruction is
  /// the candidate with the smallest cube-root distance to the held-out table (the projection has
  /// that table, as `matlas project` has the user's): the layout metric's optimum is not the
  /// perceptual one for mixtures.
  std::vector<std::vector<std::vector<int>>> loo_candidates;
  std::vector<std::vector<std::vector<int>>> step_pair;  ///< [config][path]: consecutive points
  std::vector<std::pair<int, int>> path_pairs;           ///< the materials each path joins

  int add_item(Eigen::VectorXd c) {
    items.push_back(std::move(c));
    return static_cast<int>(items.size() - 1);
  }
  int add_pair(int a, int b) {
    pairs.emplace_back(a, b);
    return static_cast<int>(pairs.size() - 1);
  }
};

/// The study in its phases (run() in order): Gram matrices per layout transform, latent fits per
/// configuration (layout x q) with and without each held-out material, the distance plan, one
/// streaming pass for every distance, per-configuration summaries, the recommendation.
class LayoutStudy {
public:
  LayoutStudy(const MaterialSet& set, const StudyOptions& options, ProgressSink& progress, Communicator& comm)
      : set_(set), options_(options), progress_(progress), comm_(comm), n_(static_cast<int>(set.size())),
        held_(spread_indices(n_, options.materials)), H_(held_.size()), L_(options.layouts.size()),
        Q_(options.dims.size()) {
    result_.names = set.names();
    result_.dims = options.dims;
    result_.layouts = options.layouts;
  }

  StudyResult run() {
    accumulate_grams();
    fit_configs();
    const DistancePlan plan = plan_distances();
    const CombinationResult pass = measure(plan);
    for (std::size_t c = 0; c < L_ * Q_; ++c) summarise(c, plan, pass);
    recommend();
    return std::move(result_);
  }

private:
  /// Gram matrices, one pass over the database per layout transform.
  void accumulate_grams() {
    const auto t0 = Clock::now();
    for (const LayoutTransform& layout : options_.layouts) {
      progress_.message("Gram matrices for layout " + layout.to_string());
      GramResult g;
      run_collectively(comm_, [&] {
        g = accumulate_gram(set_, layout, options_.block_columns, progress_, nullptr, {comm_.rank(), comm_.size()});
      });
      run_collectively(comm_, [&] { reduce_gram(g, !layout.is_identity(), comm_); });
      if (linear_gram_.size() == 0) {
        linear_gram_ = g.gram;
        result_.kept_columns = g.kept_columns;
      }
      layout_grams_.push_back(std::move(g.layout_gram));
    }
    result_.gram_seconds = seconds_since(t0);
  }

  /// Latent fits: per configuration, all materials plus one per left-out material (projected
  /// back into the map fitted without it).
  void fit_configs() {
    const int n = n_;
    const double columns = static_cast<double>(result_.kept_columns);
    result_.configs.resize(L_ * Q_);
    projections_.assign(L_ * Q_, std::vector<GramProjection>(H_));
    reference_residual_.assign(L_, std::vector<double>(H_));
    for (std::size_t l = 0; l < L_; ++l)
      for (std::size_t k = 0; k < H_; ++k) {
        const int h = held_[k];
        const std::vector<int> subset = indices_without(n, h);
        const Eigen::VectorXd mean_only = raw_from_centred(Eigen::VectorXd::Zero(n - 1), subset, n);
        reference_residual_[l][k] = residual_squared(layout_grams_[l], mean_only, h);
      }
    const auto t0 = Clock::now();
    const std::size_t jobs_per_config = 1 + H_;
    // This rank's contiguous share of the jobs; the ranks then exchange their results.
    const auto [first_job, last_job] = share_of(L_ * Q_ * jobs_per_config, comm_.rank(), comm_.size());
    ProgressTask fits(progress_, "fitting latent maps", last_job - first_job);
    std::mutex fits_mutex;  // ProgressTask counts from one thread at a time
    std::vector<double> job_seconds(L_ * Q_ * jobs_per_config, 0.0);
    run_collectively(comm_, [&, first_job = first_job, last_job = last_job] {
      parallel_for(first_job, last_job, [&](std::size_t lo, std::size_t hi) {
        for (std::size_t job = lo; job < hi; ++job) {
          const auto start = Clock::now();
          const std::size_t c = job / jobs_per_config, k = job % jobs_per_config;
          const std::size_t l = c / Q_;
          const int q = options_.dims[c % Q_];
          ConfigResult& config = result_.configs[c];
          if (k == 0) {
            const LatentFit fit = fit_latent(layout_grams_[l], columns, q, options_.fit);
            config.layout = options_.layouts[l];
            config.dim = q;
            config.latent = fit.latent();
            config.log_likelihood = fit.log_likelihood;
          } else {
            const int h = held_[k - 1];
            const std::vector<int> subset = indices_without(n, h);
            const LatentFit fit = fit_latent(centred_subset_gram(layout_grams_[l], subset), columns, q, options_.fit);
            projections_[c][k - 1] = project_in_gram(fit, subset, layout_grams_[l], h, options_.projection_starts);
          }
          job_seconds[job] = seconds_since(start);
          {
            std::lock_guard lock(fits_mutex);
            fits.advance();
          }
        }
      });
    });
    if (comm_.size() > 1) exchange_fits(first_job, last_job, job_seconds);
    for (std::size_t c = 0; c < L_ * Q_; ++c)
      for (std::size_t k = 0; k < jobs_per_config; ++k)
        result_.configs[c].fit_seconds += job_seconds[c * jobs_per_config + k];
    result_.fit_seconds = seconds_since(t0);
  }

  /// Every rank's fits on every rank (each rank computed jobs [first, last) of the
  /// configurations' fits): the values travel as doubles, so every rank plans the same distances.
  void exchange_fits(std::size_t first, std::size_t last, std::vector<double>& job_seconds) {
    const std::size_t jobs_per_config = 1 + H_;
    std::vector<std::vector<double>> mine;
    for (std::size_t job = first; job < last; ++job) {
      const std::size_t c = job / jobs_per_config, k = job % jobs_per_config;
      const ConfigResult& config = result_.configs[c];
      mine.push_back(k == 0 ? fit_record(job_seconds[job], config.log_likelihood, config.latent)
                            : projection_record(job_seconds[job], projections_[c][k - 1]));
    }
    const std::vector<std::vector<double>> all = all_gather_arrays(comm_, mine);
    MATLAS_CHECK_EQ(all.size(), L_ * Q_ * jobs_per_config);  // every job, in job order
    for (std::size_t job = 0; job < all.size(); ++job) {
      const std::size_t c = job / jobs_per_config, k = job % jobs_per_config;
      ConfigResult& config = result_.configs[c];
      if (k == 0) {
        config.layout = options_.layouts[c / Q_];
        config.dim = options_.dims[c % Q_];
        read_fit_record(all[job], job_seconds[job], config.log_likelihood, config.latent);
      } else {
        read_projection_record(all[job], job_seconds[job], projections_[c][k - 1]);
      }
    }
  }

  /// The tables and pairs to measure: materials, PCA reconstructions (per q and held-out
  /// material), and per configuration the projections, their candidates and latent paths.
  DistancePlan plan_distances() const {
    const int n = n_;
    DistancePlan plan;
    for (int i = 0; i < n; ++i) plan.add_item(Eigen::VectorXd::Unit(n, i));
    plan.material_pair.setConstant(n, n, -1);
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) plan.material_pair(i, j) = plan.material_pair(j, i) = plan.add_pair(i, j);
    plan.pca_pair.assign(Q_, std::vector<int>(H_));
    for (std::size_t qi = 0; qi < Q_; ++qi)
      for (std::size_t k = 0; k < H_; ++k) {
        const int h = held_[k];
        const int item = plan.add_item(pca_reconstruction(linear_gram_, indices_without(n, h), h, options_.dims[qi]));
        plan.pca_pair[qi][k] = plan.add_pair(item, h);
      }
    plan.path_pairs = choose_pairs(n, options_.pairs, options_.seed);
    plan.loo_pair.assign(L_ * Q_, std::vector<int>(H_));
    plan.loo_candidates.assign(L_ * Q_, std::vector<std::vector<int>>(H_));
    plan.step_pair.resize(L_ * Q_);
    for (std::size_t c = 0; c < L_ * Q_; ++c) {
      for (std::size_t k = 0; k < H_; ++k) {
        plan.loo_pair[c][k] = plan.add_pair(plan.add_item(projections_[c][k].coefficients), held_[k]);
        for (const Eigen::VectorXd& candidate : projections_[c][k].candidates)
          plan.loo_candidates[c][k].push_back(plan.add_pair(plan.add_item(candidate), held_[k]));
      }
      plan_paths(c, plan);
    }
    return plan;
  }

  /// Configuration c's latent paths: path_segments steps between each pair of materials, the
  /// points between interpolated by the configuration's map (its convex weights when the fit
  /// uses them).
  void plan_paths(std::size_t c, DistancePlan& plan) const {
    const int n = n_;
    const std::vector<int> everyone = indices_without(n, -1);
    const ConfigResult& config = result_.configs[c];
    const gp::GpPosterior posterior(config.latent, gp::Kernel{1.0, options_.fit.nugget});
    std::unique_ptr<gp::ConvexProjection> convex;
    if (options_.fit.convex_ridge > 0)
      convex = std::make_unique<gp::ConvexProjection>(layout_grams_[c / Q_], options_.fit.convex_ridge);
    plan.step_pair[c].resize(plan.path_pairs.size());
    for (std::size_t p = 0; p < plan.path_pairs.size(); ++p) {
      const auto [a, b] = plan.path_pairs[p];
      const Eigen::VectorXd xa = config.latent.row(a).transpose(), xb = config.latent.row(b).transpose();
      int previous = a;
      for (int s = 1; s <= options_.path_segments; ++s) {
        int next = b;
        if (s < options_.path_segments) {
          const double t = static_cast<double>(s) / options_.path_segments;
          const Eigen::VectorXd x = (1.0 - t) * xa + t * xb;
          const Eigen::VectorXd w = posterior.weights(x);
          next = plan.add_item(raw_from_weights(convex ? convex->from_centred(w) : w, everyone, n));
        }
        plan.step_pair[c][p].push_back(plan.add_pair(previous, next));
        previous = next;
      }
    }
  }

  /// One streaming pass for every perceptual distance; fills the material distance matrices.
  CombinationResult measure(const DistancePlan& plan) {
    const int n = n_;
    const auto t0 = Clock::now();
    CombinationQuery query;
    query.coefficients.resize(static_cast<Eigen::Index>(plan.items.size()), n);
    for (std::size_t i = 0; i < plan.items.size(); ++i)
      query.coefficients.row(static_cast<Eigen::Index>(i)) = plan.items[i].transpose();
    query.pairs = plan.pairs;
    query.gram_items = n;  // the materials, items 0..n-1: all their pairs through their Gram
    query.value_stride = options_.value_stride > 0 ? options_.value_stride
                                                   : automatic_stride(plan.items.size(), 3 * set_.dims().bins(),
                                                                      options_.compared_values_budget);
    result_.value_stride = query.value_stride;
    progress_.message("perceptual distances: " + std::to_string(plan.items.size()) + " tables, " +
                      std::to_string(plan.pairs.size()) + " pairs, every " +
                      (query.value_stride == 1 ? std::string("value") : std::to_string(query.value_stride) + "th value") +
                      (options_.value_stride > 0 ? "" : " (--stride 1 for all)"));
    query.share = {comm_.rank(), comm_.size()};  // each rank its share of the values, then their sums added up
    CombinationResult pass;
    run_collectively(comm_, [&] { pass = evaluate_combinations(set_, query, progress_); });
    reduce_combinations(pass, comm_);
    result_.pass_seconds = seconds_since(t0);
    result_.compared_values = pass.values;
    result_.material_cbrt = Eigen::MatrixXd::Zero(n, n);
    result_.material_rmse = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j) {
          const BrdfDistance& d = pass.distances[static_cast<std::size_t>(plan.material_pair(i, j))];
          result_.material_cbrt(i, j) = d.cbrt_cosine;
          result_.material_rmse(i, j) = d.cosine_rmse;
        }
    return pass;
  }

  /// Configuration c's leave-one-out errors (against PCA and the nearest material), the rank
  /// correlation of latent and perceptual distances, and its latent paths.
  void summarise(std::size_t c, const DistancePlan& plan, const CombinationResult& pass) {
    const int n = n_;
    const auto distance = [&](int pair) { return pass.distances[static_cast<std::size_t>(pair)]; };
    ConfigResult& config = result_.configs[c];
    const std::size_t qi = c % Q_;
    std::vector<double> gp_c, gp_r, pca_c, pca_r, nn_c, nn_r;
    for (std::size_t k = 0; k < H_; ++k) {
      const int h = held_[k];
      LooEntry e;
      e.material = h;
      e.gp = distance(plan.loo_pair[c][k]);
      for (const int pair : plan.loo_candidates[c][k])
        if (distance(pair).cbrt_cosine < e.gp.cbrt_cosine) e.gp = distance(pair);
      e.pca = distance(plan.pca_pair[qi][k]);
      double best = std::numeric_limits<double>::infinity();
      for (int j = 0; j < n; ++j)
        if (j != h && result_.material_cbrt(h, j) < best) best = result_.material_cbrt(h, j), e.nearest_material = j;
      e.nearest = distance(plan.material_pair(h, e.nearest_material));
      const double ref = reference_residual_[c / Q_][k];
      e.gram_residual = ref > 0 ? projections_[c][k].residual_squared / ref : 0.0;
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
        perceptual_d.push_back(result_.material_cbrt(i, j));
      }
    config.spearman_pairs = spearman(latent_d, perceptual_d);

    std::vector<double> step_latent, step_perceptual, ratios, unevenness;
    for (std::size_t p = 0; p < plan.path_pairs.size(); ++p) {
      PathEntry e;
      e.a = plan.path_pairs[p].first, e.b = plan.path_pairs[p].second;
      e.latent_distance = (config.latent.row(e.a) - config.latent.row(e.b)).norm();
      e.ends = distance(plan.material_pair(e.a, e.b));
      double length = 0, largest = 0;
      for (int id : plan.step_pair[c][p]) {
        const BrdfDistance& d = pass.distances[static_cast<std::size_t>(id)];
        e.steps.push_back(d);
        step_latent.push_back(e.latent_distance / options_.path_segments);
        step_perceptual.push_back(d.cbrt_cosine);
        length += d.cbrt_cosine;
        largest = std::max(largest, d.cbrt_cosine);
      }
      if (e.ends.cbrt_cosine > 0) ratios.push_back(length / e.ends.cbrt_cosine);
      if (length > 0) unevenness.push_back(largest / (length / options_.path_segments));
      config.paths.push_back(std::move(e));
    }
    config.spearman_steps = step_latent.size() >= 2 ? spearman(step_latent, step_perceptual)
                                                    : std::numeric_limits<double>::quiet_NaN();
    config.path_length_ratio = mean_of(ratios);
    config.path_step_unevenness = mean_of(unevenness);
  }

  /// The recommended layout: lowest leave-one-out cube-root error averaged over the dims (highest
  /// rank correlation when nothing is held out).
  void recommend() {
    std::vector<std::pair<double, std::size_t>> score;
    for (std::size_t l = 0; l < L_; ++l) {
      double loo = 0, rho = 0;
      for (std::size_t qi = 0; qi < Q_; ++qi) {
        loo += result_.configs[l * Q_ + qi].loo_gp_cbrt / static_cast<double>(Q_);
        rho += result_.configs[l * Q_ + qi].spearman_pairs / static_cast<double>(Q_);
      }
      score.emplace_back(H_ > 0 ? loo : -rho, l);
    }
    std::sort(score.begin(), score.end());
    result_.recommended = options_.layouts[score.front().second];
    char text[512];
    if (H_ > 0 && L_ > 1) {
      std::snprintf(text, sizeof text,
                    "%s: lowest leave-one-out cube-root error averaged over q (%.4f; next best %s: %.4f)",
                    result_.recommended.to_string().c_str(), score[0].first,
                    options_.layouts[score[1].second].to_string().c_str(), score[1].first);
    } else if (H_ > 0) {
      std::snprintf(text, sizeof text, "%s: the only layout evaluated (leave-one-out cube-root error %.4f)",
                    result_.recommended.to_string().c_str(), score[0].first);
    } else {
      std::snprintf(text, sizeof text, "%s: highest latent/perceptual rank correlation averaged over q (%.3f)",
                    result_.recommended.to_string().c_str(), -score[0].first);
    }
    result_.recommendation = text;
  }

  const MaterialSet& set_;
  const StudyOptions& options_;
  ProgressSink& progress_;
  Communicator& comm_;
  const int n_;
  const std::vector<int> held_;  ///< the materials left out one at a time
  const std::size_t H_, L_, Q_;  ///< held-out materials, layouts, latent dimensions
  StudyResult result_;
  Eigen::MatrixXd linear_gram_;
  std::vector<Eigen::MatrixXd> layout_grams_;
  std::vector<std::vector<GramProjection>> projections_;  ///< [config][held]
  std::vector<std::vector<double>> reference_residual_;   ///< [layout][held]: the mean's residual
};

}  // namespace

StudyResult run_layout_study(const MaterialSet& set, const StudyOptions& options, ProgressSink& progress,
                             Communicator& comm) {
  validate(set, options);
  return LayoutStudy(set, options, progress, comm).run();
}

}  // namespace matlas::eval
