#include "eval/sparse_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <random>

#include <nlohmann/json.hpp>

#include "acquisition/sample_plan.h"
#include "acquisition/sparse_fit.h"
#include "core/combination.h"
#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "eval/brdf_distance.h"
#include "eval/gram_space.h"
#include "eval/sparse_pca.h"
#include "eval/statistics.h"
#include "gp/convex_weights.h"
#include "manifold/column_blocks.h"
#include "manifold/gram.h"

namespace matlas::eval {

const SparseResult& SparseStudy::find(const std::string& method, int count) const {
  for (const auto& r : results)
    if (r.method == method && r.count == count) return r;
  throw Error("sparse study: no result for " + method + " at K = " + std::to_string(count));
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Gathers the values of chosen value indices of every material during the Gram's pass.
class ValueGather : public RawBlockVisitor {
public:
  /// targets: sorted distinct value indices; out gets one row per target (n columns).
  ValueGather(std::vector<std::size_t> targets, Eigen::Index n) : targets_(std::move(targets)), values_(targets_.size(), n) {}
  void visit(const ColumnBlock& block, std::size_t first, std::size_t last) override {
    const std::size_t lo = block.first + first, hi = block.first + last;
    auto it = std::lower_bound(targets_.begin(), targets_.end(), lo);
    for (; it != targets_.end() && *it < hi; ++it) {
      const auto row = static_cast<Eigen::Index>(it - targets_.begin());
      values_.row(row) = block.values.col(static_cast<Eigen::Index>(*it - block.first)).transpose();
    }
  }
  const std::vector<std::size_t>& targets() const { return targets_; }
  const Eigen::MatrixXd& values() const { return values_; }

private:
  std::vector<std::size_t> targets_;
  Eigen::MatrixXd values_;
};

double inverse_transform(const LayoutTransform& t, double v, double c) {
  if (t.cosine_weighted) v /= c;
  switch (t.map) {
    case LayoutTransform::Map::linear: return v;
    case LayoutTransform::Map::cube_root: return v * v * v;
    case LayoutTransform::Map::log: return std::copysign(std::expm1(std::abs(v)) / 100.0, v);
  }
  return v;
}

/// The candidates' and evaluation values' rows, with what the study needs about them.
struct StudyData {
  Eigen::MatrixXd candidate;   // 3C x n physical, rows 3c + channel
  Eigen::VectorXd candidate_cosine;  // C
  Eigen::MatrixXd evaluation;  // E x n physical
  Eigen::VectorXd evaluation_cosine;  // E: the metric's bin cosine factor
  Eigen::MatrixXd evaluation_t;  // E x n in the layout's space (bin-centre cosines)
  Eigen::MatrixXd gram;        // n x n centred Gram in the layout's space
  double columns = 0;
};

StudyData gather(const MaterialSet& set, const SparseStudyOptions& o, ProgressSink& progress) {
  const MerlDims& dims = set.dims();
  const std::size_t bins = dims.bins();
  std::mt19937_64 rng(o.seed);
  // Candidates: a random subset of the plan's lattice.
  const acquisition::PlanCandidates lattice = acquisition::plan_candidates(dims);
  std::vector<std::size_t> pick(lattice.bins.size());
  std::iota(pick.begin(), pick.end(), std::size_t{0});
  std::shuffle(pick.begin(), pick.end(), rng);
  pick.resize(std::min<std::size_t>(pick.size(), static_cast<std::size_t>(o.candidates)));
  std::sort(pick.begin(), pick.end());
  // Evaluation values: random value indices whose bin is above the horizon.
  const std::vector<double> cosine = bin_cosine_factors(dims);
  std::vector<std::size_t> above;
  for (std::size_t b = 0; b < bins; ++b)
    if (cosine[b] > 0) above.push_back(b);
  std::uniform_int_distribution<std::size_t> any_bin(0, above.size() - 1);
  std::uniform_int_distribution<int> any_channel(0, 2);
  std::vector<std::size_t> evaluation;
  for (int k = 0; k < o.evaluation_values; ++k)
    evaluation.push_back(static_cast<std::size_t>(any_channel(rng)) * bins + above[any_bin(rng)]);
  std::sort(evaluation.begin(), evaluation.end());
  evaluation.erase(std::unique(evaluation.begin(), evaluation.end()), evaluation.end());

  std::vector<std::size_t> targets = evaluation;
  for (std::size_t c : pick)
    for (std::size_t ch = 0; ch < 3; ++ch) targets.push_back(ch * bins + lattice.bins[c]);
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  const auto n = static_cast<Eigen::Index>(set.size());
  ValueGather values(targets, n);
  const GramResult g = accumulate_gram(set, o.layout, 4096, progress, &values);
  auto row_of = [&](std::size_t v) {
    return static_cast<Eigen::Index>(std::lower_bound(targets.begin(), targets.end(), v) - targets.begin());
  };

  StudyData d;
  d.gram = g.layout_gram;
  d.columns = static_cast<double>(g.kept_columns);
  std::vector<std::size_t> kept_candidates;
  for (std::size_t c : pick) {
    bool ok = true;
    for (std::size_t ch = 0; ch < 3; ++ch) ok = ok && g.kept[ch * bins + lattice.bins[c]];
    if (ok) kept_candidates.push_back(c);
  }
  const auto C = static_cast<Eigen::Index>(kept_candidates.size());
  d.candidate.resize(3 * C, n);
  d.candidate_cosine.resize(C);
  for (Eigen::Index c = 0; c < C; ++c) {
    const std::size_t k = kept_candidates[static_cast<std::size_t>(c)];
    for (std::size_t ch = 0; ch < 3; ++ch)
      d.candidate.row(3 * c + static_cast<Eigen::Index>(ch)) = values.values().row(row_of(ch * bins + lattice.bins[k]));
    d.candidate_cosine(c) = lattice.directions[k].wi.z() * lattice.directions[k].wo.z();
  }
  std::vector<std::size_t> kept_evaluation;
  for (std::size_t v : evaluation)
    if (g.kept[v]) kept_evaluation.push_back(v);
  const auto E = static_cast<Eigen::Index>(kept_evaluation.size());
  d.evaluation.resize(E, n);
  d.evaluation_cosine.resize(E);
  d.evaluation_t.resize(E, n);
  for (Eigen::Index e = 0; e < E; ++e) {
    const std::size_t v = kept_evaluation[static_cast<std::size_t>(e)];
    d.evaluation.row(e) = values.values().row(row_of(v));
    d.evaluation_cosine(e) = cosine[v % bins];
    for (Eigen::Index i = 0; i < n; ++i)
      d.evaluation_t(e, i) = acquisition::transform_value(o.layout, d.evaluation(e, i), d.evaluation_cosine(e));
  }
  return d;
}

/// The cube-root distance between a reconstruction and material h at the evaluation values.
double distance(const StudyData& d, const Eigen::VectorXd& reconstruction, Eigen::Index h) {
  DistanceSums sums;
  for (Eigen::Index e = 0; e < reconstruction.size(); ++e)
    sums.add(reconstruction(e), d.evaluation(e, h), d.evaluation_cosine(e));
  return sums.finish().cbrt_cosine;
}

/// What one left-out material gives: errors per (method, K) and per PCA ridge.
struct MaterialOutcome {
  std::map<std::pair<std::string, int>, double> error;
  std::map<std::pair<std::string, int>, std::vector<double>> pca_error;  // per ridge
  double clean = 0, corrupted = 0, corrupted_least_squares = 0, nearest = 0, fit_seconds = 0;
};

/// The PCA baseline (Nielsen et al. 2015) for the left-out material h: principal components of
/// the other materials' transformed values at the candidate directions, fitted to h's samples by
/// ridge regression at each of o.pca_ridges, and its own choice of directions (the
/// condition-number plan).
class PcaBaseline {
public:
  PcaBaseline(const StudyData& d, Eigen::Index h, const std::vector<int>& subset, const Eigen::MatrixXd& inputs,
              const Eigen::MatrixXd& centred, const SparseStudyOptions& o, int K)
      : d_(d), h_(h), o_(o), pca_(SparsePca::fit(centred)) {
    const auto n = static_cast<int>(d.gram.rows());
    const auto m = static_cast<Eigen::Index>(subset.size());
    const auto C = d.candidate_cosine.size();
    Eigen::VectorXd row_cosine(3 * C);
    for (Eigen::Index c = 0; c < C; ++c) row_cosine.segment(3 * c, 3).setConstant(d.candidate_cosine(c));
    Eigen::MatrixXd T(3 * C, m);
    for (Eigen::Index k = 0; k < m; ++k)
      for (Eigen::Index r = 0; r < 3 * C; ++r) T(r, k) = acquisition::transform_value(o.layout, inputs(r, k), row_cosine(r));
    U_ = pca_.components(T);
    mean_rows_ = T.rowwise().mean();
    conditioned_ = condition_number_plan(U_, 3, K, o.pca_condition_components);
    // The components and the mean at the evaluation values, from all n columns with h's zeroed.
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, pca_.coefficients.cols());
    for (Eigen::Index k = 0; k < m; ++k) A.row(subset[static_cast<std::size_t>(k)]) = pca_.coefficients.row(k);
    mean_eval_ = (d.evaluation_t.rowwise().sum() - d.evaluation_t.col(h)) / static_cast<double>(m);
    U_eval_ = d.evaluation_t * A - mean_eval_ * A.colwise().sum();
  }

  const std::vector<int>& conditioned() const { return conditioned_; }

  /// The reconstruction's distance to h from the first `count` of `chosen`, per ridge.
  std::vector<double> errors(const std::vector<int>& chosen, int count) const {
    Eigen::MatrixXd U_S(3 * count, U_.cols());
    Eigen::VectorXd r(3 * count);
    for (int s = 0; s < count; ++s) {
      const Eigen::Index c = chosen[static_cast<std::size_t>(s)];
      U_S.middleRows(3 * s, 3) = U_.middleRows(3 * c, 3);
      for (int ch = 0; ch < 3; ++ch)
        r(3 * s + ch) = acquisition::transform_value(o_.layout, d_.candidate(3 * c + ch, h_), d_.candidate_cosine(c)) -
                        mean_rows_(3 * c + ch);
    }
    std::vector<double> errors;
    for (double eta : o_.pca_ridges) {
      const Eigen::VectorXd t = mean_eval_ + U_eval_ * pca_.solve(U_S, r, eta);
      Eigen::VectorXd f(t.size());
      for (Eigen::Index e = 0; e < t.size(); ++e) f(e) = inverse_transform(o_.layout, t(e), d_.evaluation_cosine(e));
      errors.push_back(distance(d_, f, h_));
    }
    return errors;
  }

private:
  const StudyData& d_;
  Eigen::Index h_;
  const SparseStudyOptions& o_;
  SparsePca pca_;
  Eigen::MatrixXd U_, U_eval_;
  Eigen::VectorXd mean_rows_, mean_eval_;
  std::vector<int> conditioned_;
};

MaterialOutcome study_material(const StudyData& d, Eigen::Index h, const SparseStudyOptions& o) {
  const auto n = static_cast<int>(d.gram.rows());
  const std::vector<int> subset = indices_without(n, static_cast<int>(h));
  const auto m = static_cast<Eigen::Index>(subset.size());
  const auto C = d.candidate_cosine.size();
  // The plans serve every K and the robustness test's count (which may exceed every K).
  const int K = std::max(*std::max_element(o.counts.begin(), o.counts.end()), o.robustness_count);
  const Eigen::MatrixXd centred = centred_subset_gram(d.gram, subset);
  const LatentFit fit = fit_latent(centred, d.columns, o.dim, o.fit);

  Eigen::MatrixXd inputs(3 * C, m);
  for (Eigen::Index k = 0; k < m; ++k) inputs.col(k) = d.candidate.col(subset[static_cast<std::size_t>(k)]);
  auto full = [&](const Eigen::VectorXd& c) {  // coefficients over the subset -> over all n
    Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
    for (Eigen::Index k = 0; k < m; ++k) out(subset[static_cast<std::size_t>(k)]) = c(k);
    return out;
  };
  acquisition::MapView view;
  view.latent = fit.latent();
  view.coefficients = [&](const Eigen::VectorXd& x) {
    return Combination(fit.weights(x)).affine();
  };
  view.variance = [&](const Eigen::VectorXd& x) { return fit.posterior->variance(x); };
  view.metric = fit.convex ? fit.convex->metric() : gp::ConvexProjection(centred).metric();
  auto rows_of = [&](const std::vector<int>& chosen, int count, double corrupt_factor) {
    acquisition::SampleRows rows;
    for (int s = 0; s < count; ++s) {
      const Eigen::Index c = chosen[static_cast<std::size_t>(s)];
      Eigen::Array3d y = d.candidate.block(3 * c, h, 3, 1).array();
      const bool corrupt = corrupt_factor != 1 && s % static_cast<int>(std::lround(1 / o.outlier_share)) == 3 % static_cast<int>(std::lround(1 / o.outlier_share));
      if (corrupt) y *= corrupt_factor;
      rows.add(s, inputs.middleRows(3 * c, 3), y, Eigen::Array3d::Zero(), d.candidate_cosine(c));
    }
    return rows;
  };
  acquisition::SparseFitOptions fo;
  fo.transform = o.layout;
  MaterialOutcome out;
  auto fitted_error = [&](const std::vector<int>& chosen, int count, double corrupt_factor, const acquisition::SparseFitOptions& options) {
    const acquisition::SparseFit f = acquisition::fit_rows(view, rows_of(chosen, count, corrupt_factor), options);
    return distance(d, d.evaluation * full(f.coefficients), h);
  };

  // Directions: the map's plan, the PCA's condition-number plan, a random order.
  acquisition::PlanSpace space{inputs, d.candidate_cosine};
  acquisition::PlanOptions po;
  po.transform = o.layout;
  const std::vector<int> planned = acquisition::plan_directions(space, Eigen::VectorXd::Ones(m), nullptr, K, po).chosen;
  MATLAS_CHECK_GE(planned.size(), static_cast<std::size_t>(K));
  std::vector<int> random(static_cast<std::size_t>(C));
  std::iota(random.begin(), random.end(), 0);
  std::mt19937_64 rng(o.seed * 7919 + static_cast<unsigned>(h));
  std::shuffle(random.begin(), random.end(), rng);
  const PcaBaseline pca(d, h, subset, inputs, centred, o, K);

  for (int count : o.counts) {
    const Clock::time_point start = Clock::now();
    out.error[{"matlas-planned", count}] = fitted_error(planned, count, 1, fo);
    if (count == K) out.fit_seconds = since(start);
    out.error[{"matlas-random", count}] = fitted_error(random, count, 1, fo);
    out.pca_error[{"pca-condition", count}] = pca.errors(pca.conditioned(), count);
    out.pca_error[{"pca-random", count}] = pca.errors(random, count);
  }
  out.clean = fitted_error(planned, o.robustness_count, 1, fo);
  out.corrupted = fitted_error(planned, o.robustness_count, o.outlier_factor, fo);
  acquisition::SparseFitOptions squares = fo;
  squares.robust = false;
  out.corrupted_least_squares = fitted_error(planned, o.robustness_count, o.outlier_factor, squares);
  out.nearest = std::numeric_limits<double>::infinity();
  for (int i : subset) out.nearest = std::min(out.nearest, distance(d, d.evaluation.col(i), h));
  return out;
}

}  // namespace

SparseStudy run_sparse_study(const MaterialSet& set, const SparseStudyOptions& options, ProgressSink& progress) {
  const Clock::time_point start = Clock::now();
  if (options.counts.empty() || *std::min_element(options.counts.begin(), options.counts.end()) < 1)
    throw Error("sparse study: sample counts must be at least 1");
  if (*std::min_element(options.counts.begin(), options.counts.end()) < options.dim + 1)
    throw Error("sparse study: every K must be at least q + 1 = " + std::to_string(options.dim + 1) +
                " (a map of dimension q needs that many samples)");
  if (options.outlier_share <= 0 || options.outlier_share > 0.5) throw Error("sparse study: outlier share must be in (0, 0.5]");
  const StudyData d = gather(set, options, progress);
  const auto n = static_cast<int>(set.size());
  const int K = std::max(*std::max_element(options.counts.begin(), options.counts.end()), options.robustness_count);
  if (K > d.candidate_cosine.size())
    throw Error("sparse study: K = " + std::to_string(K) + " is more than the " + std::to_string(d.candidate_cosine.size()) +
                " candidate directions");
  if (n < options.dim + 3) throw Error("sparse study: too few materials for q = " + std::to_string(options.dim));
  std::vector<int> left_out;
  const int count = options.materials > 0 ? std::min(options.materials, n) : n;
  for (int k = 0; k < count; ++k) left_out.push_back(static_cast<int>(static_cast<long>(k) * n / count));

  std::vector<MaterialOutcome> outcomes(left_out.size());
  std::mutex lock;
  std::size_t done = 0;
  parallel_for_each(0, left_out.size(), [&](std::size_t k) {
    outcomes[k] = study_material(d, left_out[k], options);
    const std::lock_guard<std::mutex> guard(lock);
    progress.update("sparse leave-one-out", ++done, left_out.size());
  });
  progress.finish("sparse leave-one-out");

  SparseStudy study;
  for (int h : left_out) study.materials.push_back(set.name(static_cast<std::size_t>(h)));
  study.inputs = n - 1;
  study.candidates = static_cast<int>(d.candidate_cosine.size());
  study.evaluation_values = static_cast<int>(d.evaluation.rows());
  study.dim = options.dim;
  study.layout = options.layout.to_string();
  study.robustness_count = options.robustness_count;
  const auto L = static_cast<double>(outcomes.size());
  for (const auto& o : outcomes) {
    study.clean += o.clean / L;
    study.corrupted += o.corrupted / L;
    study.corrupted_least_squares += o.corrupted_least_squares / L;
    study.nearest_input += o.nearest / L;
    study.fit_seconds += o.fit_seconds / L;
  }
  auto finish = [&](SparseResult r) {
    r.mean = std::accumulate(r.error.begin(), r.error.end(), 0.0) / static_cast<double>(r.error.size());
    r.median = summarize(r.error).median;
    study.results.push_back(std::move(r));
  };
  for (const std::string method : {"matlas-planned", "matlas-random"})
    for (int c : options.counts) {
      SparseResult r{method, c, {}, 0, 0, 0};
      for (const auto& o : outcomes) r.error.push_back(o.error.at({method, c}));
      finish(std::move(r));
    }
  for (const std::string method : {"pca-condition", "pca-random"})
    for (int c : options.counts) {
      // The ridge with the lowest mean error over the materials.
      std::size_t best = 0;
      double best_mean = std::numeric_limits<double>::infinity();
      for (std::size_t e = 0; e < options.pca_ridges.size(); ++e) {
        double mean = 0;
        for (const auto& o : outcomes) mean += o.pca_error.at({method, c})[e] / L;
        if (mean < best_mean) best_mean = mean, best = e;
      }
      SparseResult r{method, c, {}, 0, 0, options.pca_ridges[best]};
      for (const auto& o : outcomes) r.error.push_back(o.pca_error.at({method, c})[best]);
      finish(std::move(r));
    }
  study.seconds = since(start);
  return study;
}

nlohmann::json sparse_study_json(const SparseStudy& s) {
  nlohmann::json results = nlohmann::json::array();
  for (const auto& r : s.results) {
    nlohmann::json j = {{"method", r.method}, {"count", r.count}, {"mean", r.mean}, {"median", r.median}, {"error", r.error}};
    if (r.method.rfind("pca", 0) == 0) j["ridge"] = r.ridge;
    results.push_back(j);
  }
  return {{"materials", s.materials},
          {"inputs_per_map", s.inputs},
          {"dim", s.dim},
          {"layout", s.layout},
          {"candidates", s.candidates},
          {"evaluation_values", s.evaluation_values},
          {"metric", "cosine-weighted cube-root distance (eval/brdf_distance.h) over the evaluation values"},
          {"results", results},
          {"robustness",
           {{"count", s.robustness_count}, {"clean", s.clean}, {"corrupted", s.corrupted},
            {"corrupted_least_squares", s.corrupted_least_squares}}},
          {"nearest_input", s.nearest_input},
          {"fit_seconds", s.fit_seconds},
          {"seconds", s.seconds}};
}

}  // namespace matlas::eval
