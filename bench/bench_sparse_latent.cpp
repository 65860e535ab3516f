// The sparse latent optimisation (gp/sparse_optimize.h) against the exact one (issue 31, item 3),
// on a generated latent problem: n latent points T uniform in [-2, 2]^2, data of 64 smooth
// features a_k sin(w_k . t + phi_k) (a_k = e^{-k/16}, w_k ~ N(0, 1.5^2 I)) plus isotropic noise of
// 2 % of the trace, so S = Y Y^T + e I is known exactly without an n x n matrix.
//   bench_sparse_latent eval [M [N]]         cost of one evaluation with gradient, sparse at
//                                           n = 1000, 3000, 10000 and exact at 1000 (and 3000)
//   bench_sparse_latent optimize N M [R]    a whole sparse placement (start + L-BFGS) at n = N
//   bench_sparse_latent converge N M R K... placements stopped after K iterations each: value,
//                                           trustworthiness, distance to the last and to the truth
//   bench_sparse_latent accuracy N R M...   exact and sparse placements of the same problem: time,
//                                           exact L of both, trustworthiness (k = 5) against the
//                                           data, leave-one-out error of the data, Procrustes
//   bench_sparse_latent models EXACT SPARSE [RIDGE]  the same comparison for two built models
//                                           (their layout Gram from the convex metric)
//   bench_sparse_latent stages MODEL Q C K...  exact placements of a model's layout Gram
//                                           stopped after K iterations: all at once (C = 0) or
//                                           coarse-to-fine (C items first, as build --coarse C);
//                                           C = -1, K = -1: the build's automatic choices.
//                                           MATLAS_BENCH_SUBSET=N: N of its items at random;
//                                           MATLAS_BENCH_VERBOSE=1: the stages' times on stderr
// q = 2, nugget 1e-4, l = 1, the build's priors (LatentPrior::spread), one start each.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "eval/manifold_quality.h"
#include "gp/coarse_placement.h"
#include "gp/initialize.h"
#include "gp/likelihood.h"
#include "gp/optimize.h"
#include "gp/sparse_optimize.h"
#include "manifold/model.h"

using namespace matlas;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// Processor seconds of this process (one thread does the work: OpenBLAS runs single-threaded), the
/// figure to read on a loaded machine.
double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// Sparse options with m inducing points; MATLAS_SPARSE_FREE=1 frees them (the FITC drift, docs/GP.md),
/// MATLAS_SPARSE_BLOCK=B sets PITC blocks, MATLAS_SPARSE_COARSE=C places C items first (coarse_placement.h;
/// 0: all at once; unset: the build's automatic choice, n / 10 from n = 2000 on).
gp::SparseOptions sopt(int m) {
  gp::SparseOptions s;
  s.inducing = m;
  const char* env = std::getenv("MATLAS_SPARSE_FREE");
  s.free_inducing = env != nullptr && std::string(env) == "1";
  if (const char* block = std::getenv("MATLAS_SPARSE_BLOCK")) s.block = std::stoi(block);
  if (const char* coarse = std::getenv("MATLAS_SPARSE_COARSE")) s.coarse = std::stoi(coarse);
  return s;
}

/// Prints the placement's stage lines (coarse stage, refinement, stop reasons) with their time,
/// not its per-iteration lines.
class StageLines final : public ProgressSink {
public:
  void update(const std::string&, std::uint64_t, std::uint64_t) override {}
  void finish(const std::string&) override {}
  void message(const std::string& line) override {
    if (line.rfind("sparse lbfgs iter", 0) == 0) {
      last_ = line;
      return;
    }
    std::printf("%8.1f s  %s\n         (%s)\n", seconds_since(start_), line.c_str(), last_.c_str());
    std::fflush(stdout);
  }

private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::string last_;
};

struct Generated {
  Eigen::MatrixXd truth;  // n x 2
  gp::SparseProblem sparse;
};

Generated generate(int n, std::uint64_t seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0), phase(0.0, 6.283185307179586);
  std::normal_distribution<double> normal(0.0, 1.5);
  Generated g;
  g.truth.resize(n, 2);
  for (int i = 0; i < n; ++i) g.truth(i, 0) = uniform(rng), g.truth(i, 1) = uniform(rng);
  constexpr int kFeatures = 64;
  Eigen::MatrixXd Y(n, kFeatures);
  for (int k = 0; k < kFeatures; ++k) {
    const double a = std::exp(-k / 16.0), w0 = normal(rng), w1 = normal(rng), p = phase(rng);
    for (int i = 0; i < n; ++i) Y(i, k) = a * std::sin(w0 * g.truth(i, 0) + w1 * g.truth(i, 1) + p);
  }
  Y = Y.rowwise() - Y.colwise().mean();
  // Orthogonal columns in decreasing order (a PCA factor), the same Y Y^T.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Y.transpose() * Y);
  g.sparse.data.factor = Y * eig.eigenvectors().rowwise().reverse();
  g.sparse.data.residual = 0.02 / 0.98 * Y.squaredNorm();
  g.sparse.columns = 1e5;
  g.sparse.kernel = gp::Kernel{1.0, 1e-4};
  g.sparse.prior = gp::LatentPrior::spread();
  return g;
}

/// The problem with the rank-r truncation of its factor (the rest of the trace into the residual).
gp::SparseProblem truncated(const gp::SparseProblem& p, int r) {
  gp::SparseProblem t = p;
  if (r < p.data.factor.cols()) {
    t.data.factor = p.data.factor.leftCols(r);
    t.data.residual += p.data.factor.rightCols(p.data.factor.cols() - r).squaredNorm();
  }
  return t;
}

gp::LikelihoodProblem exact_problem(const gp::SparseProblem& p) {
  gp::LikelihoodProblem e;
  const Eigen::Index n = p.data.factor.rows();
  e.gram = p.data.factor * p.data.factor.transpose();
  e.gram.diagonal().array() += p.data.residual / static_cast<double>(n);
  e.columns = p.columns;
  e.kernel = p.kernel;
  e.prior = p.prior;
  return e;
}

struct Timing {
  double wall = 0, cpu = 0;  // medians, seconds
};

/// Median wall and processor seconds of `reps` calls of f (the sparse repulsion runs on the
/// worker threads, so processor time exceeds wall time on an idle machine; on a loaded one the
/// processor time is the steadier figure).
template <typename F>
Timing median_seconds(int reps, F&& f) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < reps; ++i) {
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = cpu_seconds();
    f();
    cpu.push_back(cpu_seconds() - c0);
    wall.push_back(seconds_since(w0));
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

int run_eval(int m, int only_n) {
  std::printf("one evaluation with gradient (medians: wall ms / processor ms), q = 2, m = %d inducing points, r = 64\n", m);
  std::printf("%7s %18s %18s %12s\n", "n", "exact ms", "sparse ms", "exact/sparse");
  double exact_1000 = 0;
  for (int n : {1000, 3000, 10000}) {
    if (only_n > 0 && n != only_n) continue;
    const Generated g = generate(n);
    const Eigen::MatrixXd X = g.truth * 0.8;
    const Eigen::MatrixXd Z = gp::farthest_point_subset(X, m);
    gp::SparseLikelihoodEvaluator sparse(g.sparse);
    Eigen::MatrixXd gX, gZ;
    const Timing ts = median_seconds(n >= 10000 ? 5 : 11, [&] { sparse.normalized(X, Z, &gX, &gZ); });
    Timing te;
    if (n <= 3000) {
      gp::LikelihoodEvaluator exact(exact_problem(g.sparse));
      Eigen::MatrixXd gE;
      te = median_seconds(n >= 3000 ? 3 : 7, [&] { exact.normalized(X, &gE); });
      if (n == 1000) exact_1000 = te.wall;
    }
    std::printf("%7d %8.2f / %7.2f %8.2f / %7.2f %12s   sparse = %.3f x exact at n = 1000 (wall)\n", n, te.wall * 1e3,
                te.cpu * 1e3, ts.wall * 1e3, ts.cpu * 1e3, te.wall > 0 ? std::to_string(te.wall / ts.wall).c_str() : "-",
                ts.wall / exact_1000);
  }
  return 0;
}

int run_optimize(int n, int m, int r) {
  const Generated g = generate(n);
  gp::SparseProblem p = truncated(g.sparse, r);
  // MATLAS_BENCH_RADIUS: the repulsion's radius (the build's prior: 0.1); MATLAS_BENCH_ITERATIONS:
  // the L-BFGS iteration limit (5000).
  if (const char* radius = std::getenv("MATLAS_BENCH_RADIUS")) p.prior.radius = std::stod(radius);
  gp::OptimizeOptions o;
  if (const char* limit = std::getenv("MATLAS_BENCH_ITERATIONS")) o.max_iterations = std::stoi(limit);
  auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  const Eigen::MatrixXd X0 = gp::sparse_pca_initialization(p, 2, m, sopt(m).block);
  const double t_init = seconds_since(t0);
  StageLines stages;
  const gp::OptimizeResult res = gp::optimize_sparse_latent(p, X0, sopt(m), o, stages);
  std::printf("sparse placement n = %d m = %d r = %d: start %.1f s, L-BFGS %.1f s (%d iterations, %d evaluations, "
              "%.1f ms each), total %.1f s wall, %.1f s CPU; %s\n",
              n, m, r, t_init, res.seconds, res.iterations, res.evaluations, 1e3 * res.seconds / res.evaluations,
              seconds_since(t0), cpu_seconds() - c0, res.stop_reason.c_str());
  // How the value approached its last one, in the normalised units of the stopping rule (which
  // stops when 3 iterations gain at most tolerance * |l|): l_last - l after k iterations.
  const gp::SparseLikelihoodEvaluator units(p);
  const double nd = static_cast<double>(n), last = res.history.back() / p.columns;
  const double l_last = last + nd * std::log(units.scale() / p.columns);
  std::printf("l_last = %.6g (tolerance * |l_last| = %.3g)\n%10s %14s\n", l_last, o.tolerance * std::abs(l_last),
              "iteration", "l_last - l");
  for (std::size_t k = 1; k < res.history.size(); k *= 2)
    std::printf("%10zu %14.4g\n", k, last - res.history[k] / p.columns);
  return 0;
}

double procrustes_distance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const Eigen::MatrixXd A = a.rowwise() - a.colwise().mean(), B = b.rowwise() - b.colwise().mean();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B.transpose() * A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const double s = svd.singularValues().sum() / B.squaredNorm();
  return (s * B * svd.matrixU() * svd.matrixV().transpose() - A).norm() / A.norm();
}

/// How the layout approaches its optimum: placements of the same problem from the same start,
/// stopped after each of `limits` iterations (the optimisation is deterministic, so each is the
/// longer run's state at that iteration), with their value, trustworthiness (k = 5) against the
/// data's distances, and Procrustes distances to the last one and to the generating points.
int run_converge(int n, int m, int r, const std::vector<int>& limits) {
  const Generated g = generate(n);
  const gp::SparseProblem p = truncated(g.sparse, r);
  const Eigen::MatrixXd X0 = gp::sparse_pca_initialization(p, 2, m, sopt(m).block);
  const Eigen::MatrixXd& Y = g.sparse.data.factor;
  const Eigen::VectorXd norms = Y.rowwise().squaredNorm();
  const Eigen::MatrixXd D = ((-2.0 * (Y * Y.transpose())).colwise() + norms).rowwise() + norms.transpose();
  const gp::SparseLikelihoodEvaluator units(p);
  const double offset = static_cast<double>(n) * std::log(units.scale() / p.columns);
  std::vector<gp::OptimizeResult> runs;
  for (int limit : limits) {
    gp::OptimizeOptions o;
    o.max_iterations = limit;
    runs.push_back(gp::optimize_sparse_latent(p, X0, sopt(m), o, null_progress()));
  }
  std::printf("n = %d, m = %d, r = %d; generating points: trust5 %.4f\n", n, m, r, eval::trustworthiness(D, g.truth, 5));
  std::printf("%10s %12s %9s %9s %16s %16s  %s\n", "limit", "l", "seconds", "trust5", "to last layout", "to generating",
              "stop");
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const gp::OptimizeResult& res = runs[k];
    std::printf("%10d %12.2f %9.1f %9.4f %16.4f %16.4f  %s\n", limits[k], res.value / p.columns + offset, res.seconds,
                eval::trustworthiness(D, res.latent, 5), procrustes_distance(runs.back().latent, res.latent),
                procrustes_distance(g.truth, res.latent), res.stop_reason.c_str());
  }
  return 0;
}


/// Leave-one-out error of the data under the exact GP of layout X (nugget delta): the mean of the
/// others predicts each item; sum_i |[K^-1 Z]_i|^2 / [K^-1]_ii^2 over tr(S) (closed form).
double loo_error(const Eigen::MatrixXd& S, const Eigen::MatrixXd& X, const gp::Kernel& k) {
  const Eigen::MatrixXd Kinv = gp::covariance_matrix(X, k).llt().solve(Eigen::MatrixXd::Identity(X.rows(), X.rows()));
  const Eigen::MatrixXd KSK = Kinv * S * Kinv;
  double sum = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) sum += KSK(i, i) / (Kinv(i, i) * Kinv(i, i));
  return sum / S.trace();
}

Eigen::MatrixXd gram_distances(const Eigen::MatrixXd& S) {
  const Eigen::VectorXd d = S.diagonal();
  return ((-2.0 * S).colwise() + d).rowwise() + d.transpose();
}

void compare(const gp::LikelihoodProblem& e, const Eigen::MatrixXd& exact, const Eigen::MatrixXd& sparse,
             const char* label) {
  gp::LikelihoodEvaluator ev(e);
  const Eigen::MatrixXd D = gram_distances(e.gram);
  std::printf("%s\n  %-8s %14s %9s %9s\n", label, "layout", "exact l/n", "trust5", "LOO");
  for (const auto& [name, X] : {std::pair<const char*, const Eigen::MatrixXd*>{"exact", &exact}, {"sparse", &sparse}})
    std::printf("  %-8s %14.6f %9.4f %9.4f\n", name, ev.normalized(*X) / static_cast<double>(X->rows()),
                eval::trustworthiness(D, *X, 5), loo_error(e.gram, *X, e.kernel));
  std::printf("  Procrustes distance exact vs sparse: %.3f of the RMS radius\n", procrustes_distance(exact, sparse));
}

int run_accuracy(int n, int r, const std::vector<int>& ms) {
  const Generated g = generate(n);
  const gp::LikelihoodProblem e = exact_problem(g.sparse);
  gp::OptimizeOptions o;
  double c0 = cpu_seconds();
  gp::OptimizeResult exact;
  // MATLAS_BENCH_EXACT=FILE: the exact placement is read from FILE if there, else written to it
  // (its time then reads 0: the figure is from the run that wrote it).
  const char* cache = std::getenv("MATLAS_BENCH_EXACT");
  if (std::FILE* f = cache != nullptr ? std::fopen(cache, "rb") : nullptr) {
    exact.latent.resize(n, 2);
    const bool ok = std::fread(exact.latent.data(), sizeof(double), 2u * static_cast<std::size_t>(n), f) == 2u * static_cast<std::size_t>(n);
    std::fclose(f);
    if (!ok) throw std::runtime_error("short exact cache file");
    exact.stop_reason = "cached";
  } else {
    exact = gp::optimize_latent(e, gp::pca_initialization(e, 2), o, null_progress());
    if (cache != nullptr) {
      if (std::FILE* w = std::fopen(cache, "wb")) {
        std::fwrite(exact.latent.data(), sizeof(double), static_cast<std::size_t>(exact.latent.size()), w);
        std::fclose(w);
      }
    }
  }
  const double t_exact = cpu_seconds() - c0;
  std::printf("n = %d: exact placement %.1f s CPU (%d evaluations, %s)\n", n, t_exact, exact.evaluations,
              exact.stop_reason.c_str());
  std::printf("  truth: trust5 %.4f, LOO %.4f\n", eval::trustworthiness(gram_distances(e.gram), g.truth, 5),
              loo_error(e.gram, g.truth, e.kernel));
  for (int m : ms) {
    const gp::SparseProblem p = truncated(g.sparse, r);
    c0 = cpu_seconds();
    const gp::OptimizeResult sparse =
        gp::optimize_sparse_latent(p, gp::sparse_pca_initialization(p, 2, m, sopt(m).block), sopt(m), o, null_progress());
    const double t_sparse = cpu_seconds() - c0;
    std::printf("sparse m = %d r = %d block %d: %.1f s CPU (%d evaluations, %s): %.2f x faster than exact\n", m, r, sopt(m).block, t_sparse,
                sparse.evaluations, sparse.stop_reason.c_str(), t_exact / t_sparse);
    compare(e, exact.latent, sparse.latent, "layouts (generated problem)");
    std::fflush(stdout);
  }
  return 0;
}

int run_models(const char* exact_path, const char* sparse_path, double ridge) {
  const Model a = Model::open(exact_path), b = Model::open(sparse_path);
  gp::LikelihoodProblem e;
  e.gram = a.convex_metric();
  e.gram.diagonal().array() -= ridge;
  e.columns = static_cast<double>(a.kept_columns());
  e.kernel = gp::Kernel{1.0, 1e-4};
  e.prior = gp::LatentPrior::spread();
  compare(e, a.latent(), b.latent(), "layouts (built models)");
  return 0;
}

/// Both placements on a built model's layout Gram (one start each, as the others here).
int run_gram(const char* path, int m, int r, double ridge) {
  const Model a = Model::open(path);
  gp::LikelihoodProblem e;
  e.gram = a.convex_metric();
  e.gram.diagonal().array() -= ridge;
  e.columns = static_cast<double>(a.kept_columns());
  e.kernel = gp::Kernel{1.0, 1e-4};
  e.prior = gp::LatentPrior::spread();
  gp::OptimizeOptions o;
  auto t0 = std::chrono::steady_clock::now();
  const gp::OptimizeResult exact = gp::optimize_latent(e, gp::pca_initialization(e, 2), o, null_progress());
  const double t_exact = seconds_since(t0);
  const gp::SparseProblem p = gp::sparse_problem(e, r);
  t0 = std::chrono::steady_clock::now();
  const gp::OptimizeResult sparse =
      gp::optimize_sparse_latent(p, gp::sparse_pca_initialization(p, 2, m, sopt(m).block), sopt(m), o, null_progress());
  std::printf("n = %d: exact %.2f s, sparse m = %d r = %d %.2f s\n", a.count(), t_exact, m, r, seconds_since(t0));
  compare(e, exact.latent, sparse.latent, "layouts (layout Gram of a built model)");
  return 0;
}

/// Exact placements of a built model's layout Gram in q dimensions, stopped after each of `limits`
/// iterations, from PCA: all at once (coarse 0) or coarse-to-fine (`OptimizeOptions::coarse`, as
/// `matlas build --coarse`); time (the start included), l / n, trustworthiness (k = 5) and
/// leave-one-out error of each.
/// Progress messages with the seconds since the sink was made, on stderr (MATLAS_BENCH_VERBOSE=1 in
/// `stages`: where a placement's time goes).
class StampedProgress final : public ProgressSink {
public:
  void update(const std::string&, std::uint64_t, std::uint64_t) override {}
  void message(const std::string& line) override {
    if (line.rfind("lbfgs iter", 0) != 0) std::fprintf(stderr, "  [%7.2f s] %s\n", seconds_since(begin_), line.c_str());
  }
  void finish(const std::string&) override {}

private:
  std::chrono::steady_clock::time_point begin_ = std::chrono::steady_clock::now();
};

int run_stages(const char* path, int q, int coarse, const std::vector<int>& limits) {
  const Model a = Model::open(path);
  gp::LikelihoodProblem e;
  e.gram = a.convex_metric();
  e.gram.diagonal().array() -= 1e-2;
  e.columns = static_cast<double>(a.kept_columns());
  e.kernel = gp::Kernel{1.0, 1e-4};
  e.prior = gp::LatentPrior::spread();
  if (const char* subset = std::getenv("MATLAS_BENCH_SUBSET"))  // N of the model's items (coarse_subset's sample)
    e = gp::subset_problem(e, gp::coarse_subset(e.gram.rows(), std::atoi(subset), 7));
  const Eigen::MatrixXd D = gram_distances(e.gram);
  gp::LikelihoodEvaluator ev(e);
  const double n = static_cast<double>(e.gram.rows());
  for (const int k : limits) {
    gp::OptimizeOptions o;
    o.max_iterations = k;
    o.coarse = coarse;
    const auto t0 = std::chrono::steady_clock::now();
    const char* verbose = std::getenv("MATLAS_BENCH_VERBOSE");
    StampedProgress stamped;
    ProgressSink& sink = verbose != nullptr && std::string(verbose) == "1" ? stamped : null_progress();
    gp::OptimizeResult r;
    if (const char* m = std::getenv("MATLAS_BENCH_SPARSE")) {  // the sparse placement, as build --sparse-inducing M
      gp::SparseOptions so = sopt(std::atoi(m));
      const gp::SparseProblem sp = gp::sparse_problem(e, so.rank);
      const Eigen::MatrixXd X0 = gp::sparse_pca_initialization(sp, q, so.inducing, so.block);
      sink.message("PCA start");
      r = gp::optimize_sparse_latent(sp, X0, so, o, sink);
    } else {
      const gp::OptimizeOptions resolved = o.resolved(e.gram.rows());  // as the build: K = 0, C = -1 automatic
      const Eigen::MatrixXd X0 =
          gp::pca_initialization(e, q, !(resolved.coarse > 0 && resolved.coarse < e.gram.rows()));
      sink.message("PCA start");
      r = gp::optimize_latent(e, X0, resolved, sink);
    }
    const double secs = seconds_since(t0);
    const Eigen::MatrixXd Xc = r.latent.rowwise() - r.latent.colwise().mean();
    std::printf("%-14s K=%5d %7.1f s  l/n %10.5f  trust5 %.4f  LOO %.5f  rms %.3f (%s)\n",
                o.resolved(e.gram.rows()).coarse > 0 ? "coarse-to-fine" : "one stage", o.resolved(e.gram.rows()).max_iterations, secs, ev.normalized(r.latent) / n,
                eval::trustworthiness(D, r.latent, 5), loo_error(e.gram, r.latent, e.kernel),
                std::sqrt(Xc.squaredNorm() / n), r.stop_reason.c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "eval";
  const auto arg = [&](int i, int fallback) { return argc > i ? std::stoi(argv[i]) : fallback; };
  try {
    if (mode == "eval") return run_eval(arg(2, 100), arg(3, 0));
    if (mode == "optimize") return run_optimize(arg(2, 10000), arg(3, 100), arg(4, 64));
    if (mode == "converge" && argc > 5) {
      std::vector<int> limits;
      for (int k = 5; k < argc; ++k) limits.push_back(std::stoi(argv[k]));
      return run_converge(arg(2, 10000), arg(3, 100), arg(4, 64), limits);
    }
    if (mode == "accuracy") {
      std::vector<int> ms;
      for (int i = 4; i < argc; ++i) ms.push_back(std::stoi(argv[i]));
      if (ms.empty()) ms.push_back(100);
      return run_accuracy(arg(2, 1000), arg(3, 64), ms);
    }
    if (mode == "gram" && argc > 2) return run_gram(argv[2], arg(3, 30), arg(4, 64), argc > 5 ? std::stod(argv[5]) : 1e-2);
    if (mode == "stages" && argc > 5) {
      std::vector<int> limits;
      for (int k = 5; k < argc; ++k) limits.push_back(std::stoi(argv[k]));
      return run_stages(argv[2], arg(3, 5), arg(4, 0), limits);
    }
    if (mode == "models" && argc > 3) return run_models(argv[2], argv[3], argc > 4 ? std::stod(argv[4]) : 1e-2);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_sparse_latent: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "usage: %s eval [M] | optimize N M [R] | converge N M R K... | accuracy N R M... | gram MODEL M R | models EXACT SPARSE [RIDGE] | stages MODEL Q C K...\n",
               argv[0]);
  return 2;
}
